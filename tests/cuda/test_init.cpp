// Kernel 1 body: Levine eq. 5, tau' = tau - alpha min(0, eps_min), and a bond-based particle's
// limit raised by its damage (Chen eq. 18's factor).
#include <gtest/gtest.h>

#include <vector>

#include "cuda/kernels/init.h"
#include "tests/support/particle_arrays.h"

namespace pd {
namespace {

TEST(Init, CompressionStrengthensTheLimit) {
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0.25), real(-4e-3)), real(2e-3));
}

TEST(Init, TensionLeavesTheLimit) {
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0.25), real(5e-4)), real(1e-3));
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0.25), real(0)), real(1e-3));
}

TEST(Init, AlphaZeroDisablesStrengthening) {
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0), real(-1)), real(1e-3));
}

// One bond-based particle of 8 initial bonds, `intact` of them left after the last force pass.
real limit_after_init(int32_t intact, real damage_alpha) {
  testing::ParticleArrays a;
  a.rest = {{0, 0, 0, 1}};
  a.disp = {{0, 0, 0, 0}};
  a.tau0 = {real(1e-3)};
  a.smin = {real(-4e-3)};  // compressed: eq. 5 doubles the limit with alpha 0.25
  a.material = {0};
  a.intact = {intact};
  std::vector<int32_t> count{8};
  BondsView b;
  b.n = 1;
  b.count = view_of(count);
  MaterialTable mt;
  mt.count = 1;
  mt.m[0].compression_alpha = real(0.25);
  mt.m[0].damage_alpha = damage_alpha;
  init_particle<false, false>(0, a.view(), b, mt);
  return a.disp[0].w;
}

TEST(Init, DamageRaisesABondBasedLimit) {
  EXPECT_EQ(limit_after_init(8, real(3)), real(2e-3));               // undamaged: eq. 5 alone
  EXPECT_FLOAT_EQ(limit_after_init(4, real(3)), real(2e-3) * 2.5f);  // phi 1/2: 1 + 3/2
  EXPECT_FLOAT_EQ(limit_after_init(0, real(3)), real(2e-3) * 4);     // every bond gone: 1 + 3
  // alpha 0 (the default) gives eq. 5's bits whatever the damage.
  EXPECT_EQ(limit_after_init(2, real(0)), effective_strain_limit(real(1e-3), real(0.25), real(-4e-3)));
}

}  // namespace
}  // namespace pd
