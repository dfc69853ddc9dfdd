// Kernel 4 body: stretch, force, breaking, partial volumes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "cuda/kernels/springforces.h"
#include "tests/support/particle_arrays.h"

namespace pd {
namespace {

// Two particles bonded to each other, in sliced-ELL storage (one slice).
struct Pair : testing::ParticleArrays {
  std::vector<int32_t> count{1, 1}, neighbor;
  std::vector<int64_t> offset{0, kSliceWidth};
  MaterialTable mt;

  Pair(Vec3 xj, Vec3 uj, real limit) {
    rest = {{0, 0, 0, real(2e-9)}, with_w(xj, real(3e-9))};
    disp = {{0, 0, 0, limit}, with_w(uj, limit)};
    vel = force = {{0, 0, 0}, {0, 0, 0}};
    inv_mass = {1, 1};
    tau0 = {limit, limit};
    smin = {0, 0};
    material = {0, 0};
    body = {0, 0};
    intact = {1, 1};  // the bond, before the pass
    flags = {0, 0};
    ledger = {Ledger(), Ledger()};
    neighbor.assign(kSliceWidth, 0);
    neighbor[0] = 1;
    neighbor[1] = 0;
    mt.count = 1;
    mt.m[0].micromodulus = real(1e20);
    mt.m[0].horizon = real(0.01);
    mt.m[0].spacing = real(0.001);
    mt.m[0].partial_volumes = 0;
  }
  BondsView bonds() {
    BondsView b;
    b.n = 2;
    b.slice_offset = view_of(offset);
    b.count = view_of(count);
    b.neighbor = view_of(neighbor);
    return b;
  }
  void run() {
    for (int i = 0; i < 2; ++i) spring_forces<false, false>(i, view(), bonds(), mt, &broke);
  }
};

TEST(SpringForces, StretchedBondForceMatchesFormula) {
  const Vec3 xj{real(0.003), real(0.004), 0};  // |xi| = 5 mm
  const Vec3 uj{real(3e-6), real(4e-6), 0};    // stretch 1e-3 along the bond
  Pair pair(xj, uj, real(0.5));
  pair.run();
  const double s = 1e-3;
  const double expected = 1e20 * s * 2e-9 * 3e-9;  // c s V_i V_j
  const Vec3 f = pair.force[0];
  EXPECT_NEAR(f.x, expected * 0.6, 1e-4 * expected);
  EXPECT_NEAR(f.y, expected * 0.8, 1e-4 * expected);
  EXPECT_NEAR(f.z, 0, 1e-6 * expected);
  // Newton's third law, and the minimum stretch recorded for eq. 5.
  EXPECT_FLOAT_EQ(pair.force[1].x, -f.x);
  EXPECT_FLOAT_EQ(pair.force[1].y, -f.y);
  EXPECT_NEAR(pair.smin[0], s, 1e-6);
  EXPECT_EQ(pair.intact[0], 1);
  EXPECT_EQ(pair.broke, 0);
}

TEST(SpringForces, ElongationHasNoCancellation) {
  const Vec3 xi{real(0.3), real(-0.2), real(0.1)};
  const Vec3 eta{real(1e-7), real(3e-8), real(-2e-8)};
  const double r0 = std::sqrt(0.09 + 0.04 + 0.01);
  const double dx = 0.3 + 1e-7, dy = -0.2 + 3e-8, dz = 0.1 - 2e-8;
  const double exact = std::sqrt(dx * dx + dy * dy + dz * dz) - r0;
  const real r = length(xi + eta);
  EXPECT_NEAR(bond_elongation(xi, eta, length(xi) + r), exact, 1e-4 * std::fabs(exact));
}

TEST(SpringForces, BondPastItsLimitBreaksFromBothEnds) {
  Pair pair({real(0.005), 0, 0}, {real(1e-5), 0, 0}, real(1e-3));  // stretch 2e-3 > 1e-3
  pair.disp[1].w = real(1.5e-3);                                   // max(tau_i, tau_j) still below
  pair.run();
  EXPECT_LT(pair.neighbor[0], 0);
  EXPECT_LT(pair.neighbor[1], 0);
  EXPECT_EQ(bond_partner(pair.neighbor[0]), 1);
  EXPECT_EQ(pair.intact[0], 0);
  EXPECT_EQ(pair.intact[1], 0);
  EXPECT_EQ(pair.broke, 1);  // the flag that keeps the next passes on the breaking form
  EXPECT_EQ(pair.force[0].x, 0);
}

TEST(SpringForces, BondHoldsBelowTheLargerLimit) {
  Pair pair({real(0.005), 0, 0}, {real(1e-5), 0, 0}, real(1e-3));
  pair.disp[1].w = real(2.5e-3);  // the larger of the two limits decides
  pair.run();
  EXPECT_GE(pair.neighbor[0], 0);
  EXPECT_GE(pair.neighbor[1], 0);
}

TEST(SpringForces, PartialVolumeFraction) {
  Material m;
  m.horizon = real(3);
  m.spacing = real(1);
  m.partial_volumes = 1;
  EXPECT_FLOAT_EQ(volume_fraction(real(2.5), m), 1);
  EXPECT_FLOAT_EQ(volume_fraction(real(2.0), m), 1);
  EXPECT_FLOAT_EQ(volume_fraction(real(3.0), m), 0.5);
  EXPECT_FLOAT_EQ(volume_fraction(real(2.75), m), 0.75);
  m.partial_volumes = 0;
  EXPECT_FLOAT_EQ(volume_fraction(real(3.0), m), 1);
}

// The rule taken once per particle (PartialVolumes, the state-based loops) gives the per-bond
// form's bits at every length, with partial volumes and without, at spacings whose half and
// horizons whose sums round.
TEST(BondGeometry, PartialVolumesAsTaken) {
  for (const real spacing : {real(1), real(8.363e-4), real(3.3e-3) / real(3)}) {
    for (const real over : {real(3), real(4), real(3.0001), real(2.5)}) {
      for (const uint8_t partial : {uint8_t(0), uint8_t(1)}) {
        Material m;
        m.spacing = spacing;
        m.horizon = over * spacing;
        m.partial_volumes = partial;
        const PartialVolumes rule = partial_volumes_of(m);
        for (int k = 0; k <= 4000; ++k) {
          const real r0 = real(k) * real(1.25e-3) * m.horizon;
          const real per_bond = volume_fraction(r0, m), taken = volume_fraction(r0, rule);
          ASSERT_EQ(std::memcmp(&per_bond, &taken, sizeof(real)), 0)
              << "r0 " << r0 << " spacing " << spacing << " horizon " << m.horizon << " partial "
              << int(partial);
        }
      }
    }
  }
}

}  // namespace
}  // namespace pd
