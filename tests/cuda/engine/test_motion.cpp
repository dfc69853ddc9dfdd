// Scripted motion: keyframed paths, the rotation R - I without cancellation, and what apply()
// writes into the step parameters.
#include <gtest/gtest.h>

#include <cmath>

#include "cuda/engine/motion.h"

namespace pd {
namespace {

TEST(Motion, PathRestsBeforeAndAfterAndMovesLinearlyBetween) {
  const std::vector<Keyframe> path = {{0.1, 0, 0, 0}, {0.3, 2, 0, -1}, {0.4, 2, 1, -1}};
  PathSample s = sample_path(path, 0.0);
  EXPECT_EQ(s.position[0], 0);
  EXPECT_EQ(s.velocity[0], 0);
  s = sample_path(path, 0.2);
  EXPECT_NEAR(s.position[0], 1, 1e-15);
  EXPECT_NEAR(s.position[2], -0.5, 1e-15);
  EXPECT_NEAR(s.velocity[0], 10, 1e-12);
  EXPECT_NEAR(s.velocity[2], -5, 1e-12);
  s = sample_path(path, 0.35);
  EXPECT_NEAR(s.position[1], 0.5, 1e-14);
  EXPECT_NEAR(s.velocity[1], 10, 1e-12);
  EXPECT_EQ(s.velocity[0], 0);
  s = sample_path(path, 1.0);
  EXPECT_EQ(s.position[1], 1);
  EXPECT_EQ(s.velocity[1], 0);
  // Exactly at a keyframe: the point itself, moving along the segment that starts there.
  s = sample_path(path, 0.3);
  EXPECT_EQ(s.position[0], 2);
  EXPECT_NEAR(s.velocity[1], 10, 1e-12);
}

// R from the textbook Rodrigues formula, R = I + sin(a) K + (1 - cos a) K^2, minus I.
std::array<double, 9> reference_rotation_minus_identity(std::array<double, 3> w, double t) {
  const double rate = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), a = rate * t;
  const double x = w[0] / rate, y = w[1] / rate, z = w[2] / rate;
  const double c = std::cos(a), s = std::sin(a), v = 1 - c;
  return {c + x * x * v - 1, x * y * v - z * s, x * z * v + y * s, y * x * v + z * s, c + y * y * v - 1,
          y * z * v - x * s, z * x * v - y * s, z * y * v + x * s, c + z * z * v - 1};
}

TEST(Motion, RotationMinusIdentityIsRodriguesAndKeepsSmallAngles) {
  const std::array<double, 3> w = {0.3, -1.2, 0.7};
  const auto m = rotation_minus_identity(w, 0.9), ref = reference_rotation_minus_identity(w, 0.9);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(m[size_t(k)], ref[size_t(k)], 1e-15) << k;
  // R is orthogonal: (M + I)^T (M + I) = I.
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      double sum = 0;
      for (int j = 0; j < 3; ++j)
        sum += (m[size_t(3 * j + r)] + (j == r)) * (m[size_t(3 * j + c)] + (j == c));
      EXPECT_NEAR(sum, r == c ? 1 : 0, 1e-15);
    }
  // A tiny angle about z: R - I = [[-a^2/2, -a, 0], [a, -a^2/2, 0], [0, 0, 0]] to relative 1e-15,
  // where forming R and subtracting I would keep no digit of the a^2 terms.
  const double a = 1e-9;
  const auto small = rotation_minus_identity({0, 0, 1}, a);
  EXPECT_NEAR(small[1], -a, 1e-15 * a);
  EXPECT_NEAR(small[3], a, 1e-15 * a);
  EXPECT_NEAR(small[0], -0.5 * a * a, 1e-12 * a * a);
  EXPECT_EQ(rotation_minus_identity({0, 0, 0}, 5.0), (std::array<double, 9>{}));
}

TEST(Motion, ApplyWritesAnchorsAndKeyframedProjectiles) {
  MotionScript script;
  AnchorScript held;  // unscripted: particles keep their own velocity
  AnchorScript turning;
  turning.pivot = {1, 0, 0};
  turning.omega = {0, 0, 2};
  turning.velocity = {0.5, 0, 0};
  turning.release = 0.25;
  script.anchors = {held, turning};
  script.projectiles = {{}, {{0, 0, 0, 1}, {0.5, 0, 0, -1}}};
  EXPECT_FALSE(script.empty());

  StepParams sp;
  sp.n_projectiles = 2;
  sp.projectile[0].velocity = {0, 0, 3};
  script.apply(0.2, sp);
  EXPECT_EQ(sp.anchor[0].scripted, 0);
  EXPECT_EQ(sp.anchor[0].released, 0);
  EXPECT_EQ(sp.anchor[1].scripted, 1);
  EXPECT_EQ(sp.anchor[1].released, 0);
  EXPECT_FLOAT_EQ(sp.anchor[1].offset.x, 0.1f);
  EXPECT_FLOAT_EQ(sp.anchor[1].rotation_minus_identity[3], real(std::sin(0.4)));
  EXPECT_EQ(sp.projectile[0].velocity.z, 3);  // not keyframed: left alone
  const Projectile& p = sp.projectile[1];
  EXPECT_FLOAT_EQ(p.velocity.z, -4);
  EXPECT_NEAR(p.center0.z + 0.2 * p.velocity.z, 1 - 0.8, 1e-6);  // on the path at t = 0.2
  script.apply(0.25, sp);
  EXPECT_EQ(sp.anchor[1].released, 1);
}

TEST(Motion, ConstantAnchorsAreNotAScript) {
  MotionScript script;
  script.anchors.resize(3);
  script.anchors[1].velocity = {1, 0, 0};
  script.projectiles.resize(2);
  EXPECT_TRUE(script.empty());
}

}  // namespace
}  // namespace pd
