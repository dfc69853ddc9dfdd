// The contact lists' frame (cuda/kernels/contact_frame.h): the moving frame is taken where the
// particles move together, and the frame at rest everywhere else.
#include "cuda/kernels/contact_frame.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace pd {
namespace {

VelocityMoments moments(const std::vector<Vec3>& velocities) {
  VelocityMoments m;
  for (const Vec3& v : velocities) m = m + velocity_moments_of(v);
  return m;
}

TEST(ContactFrame, MovesWithParticlesThatMoveTogether) {
  // A body in free fall, shaking a little: the moving frame.
  std::vector<Vec3> fall;
  for (int i = 0; i < 100; ++i) fall.push_back({real(0.01 * (i % 3 - 1)), real(-5 + 0.02 * (i % 5 - 2)), 0});
  EXPECT_TRUE(moving_frame_wins(moments(fall), int64_t(fall.size())));
  const VelocityMoments m = moments(fall);
  EXPECT_NEAR(m.y / double(fall.size()), -5.0, 1e-6);
}

TEST(ContactFrame, StaysAtRestWhereTheParticlesDoNotMoveTogether) {
  const std::vector<Vec3> still(50, Vec3{0, 0, 0});
  EXPECT_FALSE(moving_frame_wins(moments(still), int64_t(still.size())));
  // Flying apart: the mean is at rest.
  const std::vector<Vec3> burst{{30, 0, 0}, {-30, 0, 0}, {0, 30, 0}, {0, -30, 0}};
  EXPECT_FALSE(moving_frame_wins(moments(burst), int64_t(burst.size())));
  // Half at rest, half moving alike: in either frame half of them move at half the speed.
  std::vector<Vec3> half(50, Vec3{0, 0, 0});
  half.resize(100, Vec3{0, -5, 0});
  EXPECT_FALSE(moving_frame_wins(moments(half), int64_t(half.size())));
  // Nine in ten moving alike: at rest still; 999 in 1,000: the moving frame.
  std::vector<Vec3> most(10, Vec3{0, 0, 0});
  most.resize(100, Vec3{0, -5, 0});
  EXPECT_FALSE(moving_frame_wins(moments(most), int64_t(most.size())));
  most.assign(1, Vec3{0, 0, 0});
  most.resize(1000, Vec3{0, -5, 0});
  EXPECT_TRUE(moving_frame_wins(moments(most), int64_t(most.size())));
}

TEST(ContactFrame, NonFiniteVelocitiesOrNoParticlesKeepTheFrameAtRest) {
  std::vector<Vec3> fall(10, Vec3{0, -5, 0});
  fall[3].x = std::numeric_limits<real>::quiet_NaN();
  EXPECT_FALSE(moving_frame_wins(moments(fall), int64_t(fall.size())));
  fall[3].x = std::numeric_limits<real>::infinity();
  EXPECT_FALSE(moving_frame_wins(moments(fall), int64_t(fall.size())));
  EXPECT_FALSE(moving_frame_wins(VelocityMoments{}, 0));
}

}  // namespace
}  // namespace pd
