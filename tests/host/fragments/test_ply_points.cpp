// PLY point files: round trip, the header other tools read, files from elsewhere, refused files.
#include "host/fragments/ply_points.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "host/geometry/random.h"
#include "host/io/atomic_file.h"
#include "tests/host/fragments/fragment_fixtures.h"

namespace pd {
namespace {

using PlyPointsTest = testing::TempDirTest;

FrameData random_frame(size_t n, bool component, uint64_t seed) {
  Random rng(seed);
  FrameData f;
  f.frame = 12;
  f.step = 34567;
  f.time = 0.001234567890123;
  for (size_t i = 0; i < n; ++i) {
    f.position.push_back({real(rng.normal()), real(rng.normal()), real(rng.normal())});
    f.velocity.push_back({real(rng.normal()), real(rng.normal()), real(rng.normal())});
    f.damage.push_back(float(rng.uniform()));
    f.body.push_back(int32_t(i % 3));
    if (component) f.component.push_back(int32_t(i / 4));
  }
  return f;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(PlyPointsTest, RoundTrip) {
  for (bool component : {true, false})
    for (size_t n : {0, 1, 1000}) {
      const FrameData f = random_frame(n, component, n + 3);
      const std::string p = path(points_file_name(f.frame));
      write_ply_points(p, f);
      const FrameData back = read_ply_points(p);
      EXPECT_EQ(back.frame, f.frame);
      EXPECT_EQ(back.step, f.step);
      EXPECT_EQ(back.time, f.time);
      ASSERT_EQ(back.size(), n);
      for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(float(back.position[i].x), float(f.position[i].x));
        EXPECT_EQ(float(back.position[i].z), float(f.position[i].z));
        EXPECT_EQ(float(back.velocity[i].y), float(f.velocity[i].y));
        EXPECT_EQ(back.damage[i], f.damage[i]);
        EXPECT_EQ(back.body[i], f.body[i]);
      }
      EXPECT_EQ(back.component, f.component);
    }
}

TEST_F(PlyPointsTest, HeaderAndRecordLayout) {
  const FrameData f = random_frame(2, true, 5);
  const std::string p = path("p.ply");
  write_ply_points(p, f);
  const std::string b = read_all(p);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment perifrac frame 12 step 34567 time 0.001234567890123\n"
      "element vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float vx\n"
      "property float vy\nproperty float vz\nproperty float damage\nproperty int body\nproperty int "
      "component\n"
      "end_header\n";
  ASSERT_EQ(b.substr(0, header.size()), header);
  ASSERT_EQ(b.size(), header.size() + 2 * 36);
  float x1;
  int32_t component1;
  std::memcpy(&x1, b.data() + header.size() + 36, 4);
  std::memcpy(&component1, b.data() + header.size() + 36 + 32, 4);
  EXPECT_EQ(x1, float(f.position[1].x));
  EXPECT_EQ(component1, 0);
}

TEST_F(PlyPointsTest, ReadsOtherScalarTypesAndSkipsLaterElements) {
  // double coordinates, uchar damage, no velocity, a face element after the vertices.
  std::string b =
      "ply\nformat binary_little_endian 1.0\ncomment from elsewhere\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nproperty uchar damage\nelement face 0\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 2; ++i) {
    const double xyz[3] = {1.5 + i, -2.0, 3.25};
    b.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    b.push_back(char(i));
  }
  const std::string p = path("other.ply");
  write_file_atomic(p, b);
  const FrameData f = read_ply_points(p);
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f.position[1].x, real(2.5));
  EXPECT_EQ(f.position[1].z, real(3.25));
  EXPECT_EQ(f.velocity[1].x, 0);
  EXPECT_EQ(f.damage[1], 1.0f);
  EXPECT_TRUE(f.component.empty());
}

TEST_F(PlyPointsTest, RefusesBadFiles) {
  const std::string p = path("bad.ply");
  auto expect_refused = [&](const std::string& bytes, const std::string& reason) {
    write_file_atomic(p, bytes);
    try {
      read_ply_points(p);
      ADD_FAILURE() << "accepted: " << reason;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  expect_refused("PLY\n", "not a PLY file");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "end_header\n1 2 3\n", "format 'ascii'");
  expect_refused("ply\nformat binary_little_endian 1.0\nelement vertex 1\n" + xyz, "no end_header");
  expect_refused("ply\nformat binary_little_endian 1.0\nelement face 1\nend_header\n",
                 "first element is 'face'");
  expect_refused("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nend_header\n" +
                     std::string(4, '\0'),
                 "no x, y and z");
  expect_refused("ply\nformat binary_little_endian 1.0\nelement vertex 1000\n" + xyz + "end_header\n" +
                     std::string(12, '\0'),
                 "truncated");
  expect_refused(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty list uchar int x\nend_header\n",
      "not a scalar property");
  EXPECT_THROW(read_ply_points(path("missing.ply")), IoError);
  FrameData bad = random_frame(3, true, 1);
  bad.damage.pop_back();
  EXPECT_THROW(write_ply_points(p, bad), std::invalid_argument);
}

}  // namespace
}  // namespace pd
