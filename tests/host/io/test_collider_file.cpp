// colliders_NNNNN.csv (host/io/collider_file.h): written and read back with the same poses,
// quaternions that turn as the rotation does, and malformed files refused with the line.
#include "host/io/collider_file.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/io/atomic_file.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

// A rotation by `angle` about the unit axis (x, y, z), row major.
void axis_angle(double x, double y, double z, double angle, real* m) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  const double r[9] = {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
                       t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
                       t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  for (int i = 0; i < 9; ++i) m[i] = real(r[i]);
}

TEST(ColliderFile, QuaternionsRoundTripEveryRotation) {
  // Angles near 0 and 180 degrees about each axis and a skew one: each branch of the conversion.
  const double axes[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.48, 0.6, 0.64}};
  for (const auto& a : axes)
    for (double angle : {0.0, 0.3, 2.0, 3.1, 3.14159}) {
      real m[9], back[9];
      axis_angle(a[0], a[1], a[2], angle, m);
      const std::array<double, 4> q = rotation_to_quaternion(m);
      EXPECT_NEAR(q[0], std::cos(angle / 2), 1e-6);
      quaternion_to_rotation(q, back);
      for (int i = 0; i < 9; ++i) EXPECT_NEAR(back[i], m[i], 1e-6) << angle;
    }
}

class ColliderFileTest : public testing::TempDirTest {};

TEST_F(ColliderFileTest, WritesAndReadsBack) {
  ColliderState a, b;
  a.collider.shape = kColliderBox;
  a.collider.size = {real(0.1), real(0.2), real(0.3)};
  a.collider.center = {1, 2, 3};
  axis_angle(0.48, 0.6, 0.64, 0.7, a.collider.rotation);
  a.collider.velocity = {4, 5, 6};
  a.collider.omega = {-1, 0, 1};
  a.mass = 2.5;
  b.collider.shape = kColliderSphere;
  b.collider.law = kLawLammpsIndent;
  b.collider.size = {real(0.05), 0, 0};
  const std::string path = this->path(colliders_file_name(7));
  EXPECT_EQ(colliders_file_name(7), "colliders_00007.csv");
  write_colliders_file(path, 7, 0.5, {a, b});
  const std::vector<ColliderState> r = read_colliders_file(path);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].collider.shape, kColliderBox);
  EXPECT_EQ(r[1].collider.law, kLawLammpsIndent);
  EXPECT_EQ(r[0].mass, 2.5);
  EXPECT_EQ(r[0].collider.size.z, real(0.3));
  EXPECT_EQ(r[0].collider.center.y, 2);
  EXPECT_EQ(r[0].collider.velocity.z, 6);
  EXPECT_EQ(r[0].collider.omega.x, -1);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(r[0].collider.rotation[i], a.collider.rotation[i], 1e-6);
}

TEST_F(ColliderFileTest, RefusesMalformedFilesNamingTheLine) {
  const std::string path = this->path("c.csv");
  ColliderState s;
  write_colliders_file(path, 0, 0, {s});
  const std::string text = testing::read_all(path);
  const std::string header = text.substr(0, text.find('\n') + 1);
  auto refused = [&](const std::string& body, const std::string& what) {
    write_file_atomic(path, body);
    try {
      read_colliders_file(path);
      ADD_FAILURE() << "accepted: " << body;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused("frame,time\n", "line 1 is not the colliders header");
  refused(header + "0,0,0,plane\n", "line 2: 4 values, expected 22");
  refused(header + "0,0,0,cone,penalty,0,0,0,0,0,0,1,0,0,0,0,0,0,0,0,0,0\n", "line 2: unknown shape 'cone'");
  refused(header + "0,0,0,plane,penalty,x,0,0,0,0,0,1,0,0,0,0,0,0,0,0,0,0\n",
          "line 2: 'x' is not a finite number");
  refused(header + "0,0,0,plane,penalty,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n", "quaternion is zero");
  EXPECT_THROW(read_colliders_file(this->path("missing.csv")), IoError);
}

}  // namespace
}  // namespace pd
