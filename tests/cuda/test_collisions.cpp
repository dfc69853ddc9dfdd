// Kernel 3 body: Levine eq. 6 quadratic repulsion.
#include <gtest/gtest.h>

#include "cuda/kernels/collisions.h"

namespace pd {
namespace {

TEST(Collisions, QuadraticRepulsionBelowTheContactDistance) {
  const real rc = real(0.5e-3), kc = real(1e8);
  const Vec3 f = contact_force({real(0.3e-3), 0, 0}, {0, 0, 0}, rc, kc);
  EXPECT_NEAR(f.x, 1e8 * 0.2e-3 * 0.2e-3, 1e-5 * 4);  // K_c (d - rc)^2, pushing i away from j
  EXPECT_EQ(f.y, 0);
  const Vec3 g = contact_force({0, 0, 0}, {real(0.3e-3), 0, 0}, rc, kc);
  EXPECT_FLOAT_EQ(g.x, -f.x);
}

TEST(Collisions, NoForceAtOrBeyondTheContactDistance) {
  EXPECT_EQ(contact_force({real(1e-3), 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);
  EXPECT_EQ(contact_force({real(2e-3), 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);
  EXPECT_EQ(contact_force({0, 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);  // coincident: no direction
}

}  // namespace
}  // namespace pd
