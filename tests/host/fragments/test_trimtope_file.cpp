// trimtopes.ptm (render/trimtope_file.h): round trip in float32, shared planes stay exact
// negatives, and damaged files are refused.
#include "host/fragments/trimtope_file.h"

#include <gtest/gtest.h>

#include <limits>

#include <unistd.h>
#include <cstring>

#include <filesystem>
#include <fstream>

#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"
#include "host/io/atomic_file.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

class TrimtopeFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (fs::path(::testing::TempDir()) / ("perifrac_trimtopes_" + std::to_string(getpid()) + ".ptm"))
                .string();
    const ParticleGeometry g = voronoi_particles(sphere_mesh(0.3, 0.06), 0.05, 2, 100000, "sphere");
    rest_ = rest_trimtopes(g, 10);
    write_trimtopes_file(path_, rest_);
  }
  void TearDown() override { fs::remove(path_); }
  std::string path_;
  RestTrimtopes rest_;
};

TEST_F(TrimtopeFile, RoundTripInFloat32) {
  const RestTrimtopes back = read_trimtopes_file(path_);
  ASSERT_EQ(back.size(), rest_.size());
  EXPECT_EQ(back.particle, rest_.particle);
  EXPECT_EQ(back.particle[0], 10);
  EXPECT_EQ(back.plane_start, rest_.plane_start);
  EXPECT_EQ(back.tri_start, rest_.tri_start);
  ASSERT_EQ(back.tri_vertex.size(), rest_.tri_vertex.size());
  for (size_t k = 0; k < back.plane_offset.size(); ++k) {
    EXPECT_EQ(back.plane_offset[k], double(float(rest_.plane_offset[k])));
    for (int a = 0; a < 3; ++a) EXPECT_EQ(back.plane_normal[k][a], double(float(rest_.plane_normal[k][a])));
  }
  for (size_t i = 0; i < back.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(back.box[i].lo[a], rest_.box[i].lo[a]);  // rounded outward
      EXPECT_GE(back.box[i].hi[a], rest_.box[i].hi[a]);
    }
}

TEST_F(TrimtopeFile, SharedFacesStayExactNegatives) {
  // Two neighbouring cells store their common bisector as (n, d) and (-n, -d), bit for bit.
  const RestTrimtopes back = read_trimtopes_file(path_);
  int pairs = 0;
  for (size_t i = 0; i < back.size() && pairs < 200; ++i)
    for (int64_t a = back.plane_start[i]; a < back.plane_start[i + 1]; ++a)
      for (size_t j = i + 1; j < back.size(); ++j)
        for (int64_t b = back.plane_start[j]; b < back.plane_start[j + 1]; ++b)
          if (back.plane_normal[size_t(a)][0] == -back.plane_normal[size_t(b)][0] &&
              back.plane_normal[size_t(a)][1] == -back.plane_normal[size_t(b)][1] &&
              back.plane_normal[size_t(a)][2] == -back.plane_normal[size_t(b)][2] &&
              back.plane_offset[size_t(a)] == -back.plane_offset[size_t(b)])
            ++pairs;
  EXPECT_GE(pairs, 200);
}

TEST_F(TrimtopeFile, RefusesDamagedFiles) {
  std::string bytes;
  {
    std::ifstream in(path_, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto refused = [&](std::string damaged) {
    write_file_atomic(path_, damaged);
    EXPECT_THROW(read_trimtopes_file(path_), IoError);
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
  counts[16] = char(counts[16] + 1);  // one cell more than stored
  refused(counts);
  std::string not_finite = bytes;  // the first cell's site, after the 40-byte header and n indices
  const float nan = std::numeric_limits<float>::quiet_NaN();
  uint64_t n = 0;
  std::memcpy(&n, &bytes[16], 8);
  std::memcpy(&not_finite[40 + 4 * n], &nan, 4);
  refused(not_finite);
  EXPECT_THROW(read_trimtopes_file(path_ + ".missing"), IoError);
}

}  // namespace
}  // namespace pd
