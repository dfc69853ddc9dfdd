// tets.ptt (render/tet_file.h): round trip in float32 and damaged files refused.
#include "host/fragments/tet_file.h"

#include <gtest/gtest.h>

#include <limits>

#include <unistd.h>
#include <cstring>

#include <filesystem>
#include <fstream>

#include "host/io/atomic_file.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

class TetFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ =
        (fs::path(::testing::TempDir()) / ("perifrac_tets_" + std::to_string(getpid()) + ".ptt")).string();
    // Two tets sharing the face (1, 2, 3), particles 7 and 4.
    tets_.vertices = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}, {0.1, 0.1, 0.1 / 3}};
    tets_.tets = {{0, 1, 2, 3}, {4, 1, 2, 3}};
    tets_.particle = {7, 4};
    write_tets_file(path_, tets_);
  }
  void TearDown() override { fs::remove(path_); }
  std::string path_;
  EmbeddedTets tets_;
};

TEST_F(TetFile, RoundTripInFloat32) {
  const EmbeddedTets back = read_tets_file(path_);
  EXPECT_EQ(back.tets, tets_.tets);
  EXPECT_EQ(back.particle, tets_.particle);
  ASSERT_EQ(back.vertices.size(), tets_.vertices.size());
  for (size_t v = 0; v < back.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(back.vertices[v][size_t(a)], double(float(tets_.vertices[v][size_t(a)])));
  EXPECT_EQ(fs::file_size(path_), 32u + 5 * 12 + 2 * 20);
}

TEST_F(TetFile, RefusesDamagedFiles) {
  std::string bytes;
  {
    std::ifstream in(path_, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto refused = [&](std::string damaged) {
    write_file_atomic(path_, damaged);
    EXPECT_THROW(read_tets_file(path_), IoError);
  };
  refused(bytes.substr(0, bytes.size() - 1));  // truncated
  refused(bytes + "x");                        // trailing byte
  std::string magic = bytes;
  magic[0] = 'X';
  refused(magic);
  std::string version = bytes;
  version[8] = 9;
  refused(version);
  std::string counts = bytes;
  counts[24] = char(counts[24] + 1);  // one tet more than stored
  refused(counts);
  std::string index = bytes;
  index[32 + 5 * 12] = 5;  // vertex index 5 of 5 vertices
  refused(index);
  std::string not_finite = bytes;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&not_finite[32 + 4], &nan, 4);  // the first vertex's y
  refused(not_finite);
  EXPECT_THROW(read_tets_file(path_ + ".missing"), IoError);
}

}  // namespace
}  // namespace pd
