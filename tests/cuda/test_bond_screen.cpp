// The screened force passes (cuda/kernels/bond_screen.h): the own-end test never rules out a
// bond that the breaking pass breaks, and runs screened in every pass, in none, or as the
// engine chooses give the same bits (CPU reference; tests/gpu/test_bond_screen.cpp on the GPU).
#include "cuda/kernels/bond_screen.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/geometry/random.h"
#include "tests/support/fixtures.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

// Near the breaking test's boundary x > rnd(max(L, L_j) w), in both forms of the margin (fused
// and rounded product), a bond that breaks is never ruled out by may_break.
TEST(BondScreen, OwnEndTestKeepsEveryBondThatBreaks) {
  Random rng(3);
  int64_t breaks = 0;
  for (int k = 0; k < 200000; ++k) {
    const real limit = real(std::ldexp(1.0 + rng.uniform(), -12 + int(rng.uniform() * 12)));
    const real other = rng.uniform() < 0.5 ? limit : real(limit * (1 + rng.uniform()));
    const bool weak = rng.uniform() < 0.7;
    const real w = weak ? real(std::floor(rng.uniform() * 256) / 255) : real(1);
    const real edge = std::fmax(limit, other) * w;
    // x within a few ulps of the limit, on either side.
    const real x = std::nextafter(edge, real(k % 2 ? 1 : -1)) +
                   real((int(rng.uniform() * 7) - 3)) * std::ldexp(edge, -23);
    if (!(x > std::fmax(limit, other) * w)) continue;
    ++breaks;
    const real fused = real(std::fma(-double(w), double(limit), double(x)));  // one rounding
    const real rounded = x - w * limit;
    if (weak) {
      EXPECT_TRUE(may_break<true>(fused, limit)) << x << " " << w << " " << limit;
      EXPECT_TRUE(may_break<true>(rounded, limit)) << x << " " << w << " " << limit;
    } else {
      EXPECT_TRUE(may_break<false>(x, limit)) << x << " " << limit;
    }
  }
  EXPECT_GT(breaks, 50000);
}

// Far from its limit a particle is ruled out; at it, not.
TEST(BondScreen, OwnEndTestRulesOutBondsBelowTheLimit) {
  EXPECT_FALSE(may_break<false>(real(0.9e-3), real(1e-3)));
  EXPECT_TRUE(may_break<false>(real(1.1e-3), real(1e-3)));
  EXPECT_FALSE(may_break<true>(real(-1e-5), real(1e-3)));
  EXPECT_TRUE(may_break<true>(real(0), real(1e-3)));
}

const testing::EngineFactory kCpu = [](const SimulationInput& in) { return make_cpu_engine(in); };

TEST(BondScreen, BondBasedLatticeRunsTheSameInEveryMode) {
  testing::expect_screen_modes_agree(
      kCpu, testing::pulled_apart(testing::lattice_block(16, 8, 8, kLambda, 2e-4), 16, kLambda, 2), 150);
}

TEST(BondScreen, BondBasedJitteredRunsTheSameInEveryMode) {  // explicit families
  testing::expect_screen_modes_agree(
      kCpu, testing::pulled_apart(testing::lattice_block(16, 8, 8, kLambda, 2e-4, 0.3), 16, kLambda, 2), 150);
}

TEST(BondScreen, WeakenedBondsRunTheSameInEveryMode) {
  auto in = testing::pulled_apart(testing::lattice_block(16, 8, 8, kLambda, 4e-4), 16, kLambda, 2);
  testing::weaken_plane(in, 8 * kLambda, 0.5);
  testing::expect_screen_modes_agree(kCpu, in, 150);
  in.lattice_families = false;
  testing::expect_screen_modes_agree(kCpu, in, 150);
}

TEST(BondScreen, StateBasedRunsTheSameInEveryMode) {
  auto in = testing::pulled_apart(testing::state_block(16, 8, 8, kLambda, 2e-4, false), 16, kLambda, 2);
  testing::expect_screen_modes_agree(kCpu, in, 150);
  in.materials.m[0].chen_fracture = 0;  // the stretch criterion
  testing::expect_screen_modes_agree(kCpu, in, 150);
}

TEST(BondScreen, PlasticRunsTheSameInEveryMode) {
  auto in = testing::pulled_apart(testing::state_block(16, 8, 8, kLambda, 2e-4, true), 16, kLambda, 2);
  testing::weaken_plane(in, 8 * kLambda, 0.5);
  testing::expect_screen_modes_agree(kCpu, in, 150);
}

}  // namespace
}  // namespace pd
