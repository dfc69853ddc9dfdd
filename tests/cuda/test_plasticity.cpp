// Kernel 5, `plasticity`, and the return mapping `springforces` applies to both ends of each bond:
// on a block whose every particle yields, the history stays mirrored bit for bit, each end moves
// as Chen's eqs. 13-15 say, yielding particles end on the yield surface, and forces balance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/kernels/family.h"
#include "cuda/kernels/init.h"
#include "cuda/kernels/plasticity.h"
#include "cuda/kernels/springforces_state.h"
#include "host/geometry/random.h"
#include "tests/support/fixtures.h"
#include "tests/support/particle_arrays.h"

namespace pd {
namespace {

// A plastic state-based block with its families as the engine builds them (listed families),
// every array a step reads, and a plastic history with its mirror.
struct PlasticBlock : testing::ParticleArrays {
  SimulationInput in;
  BondLists families;
  std::vector<real> plastic, mirror;

  PlasticBlock() : in(testing::state_block(7, 6, 5, 1e-3, 1.0, true)) {
    in.lattice_families = false;
    make_cpu_engine(in)->read_bonds(families);
    const ParticleSet& ps = in.particles;
    const size_t n = ps.size();
    for (size_t i = 0; i < n; ++i) {
      rest.push_back(with_w(ps.rest[i], ps.volume[i]));
      inv_mass.push_back(real(1) / ps.mass[i]);
    }
    disp.assign(n, {0, 0, 0, real(1)});
    state.assign(n, {0, 0, 0, 0});
    vel = force = std::vector<Vec3>(n, Vec3{0, 0, 0});
    tau0.assign(n, real(1));
    smin.assign(n, 0);
    intact = families.count;
    ledger.assign(n, Ledger());
    material = ps.material;
    body = ps.body;
    flags = ps.flags;
    plastic.assign(families.neighbor.size(), 0);
    mirror = plastic;
    for (int32_t i = 0; i < int32_t(n); ++i) weighted_volume(i, view(), bonds(), in.materials);
  }
  BondsView bonds() {
    BondsView b = families.view();
    b.plastic = view_of(plastic);
    b.plastic_mirror = view_of(mirror);
    return b;
  }
  // Slot of bond (i, k) in the partner's family.
  int64_t partner_slot(int32_t i, int32_t k) {
    const BondsView b = bonds();
    const int32_t j = bond_partner(b.neighbor[b.slot(i, k)]);
    return b.slot(j, position_in_family(b, j, i));
  }
  // One step's kernels 1, 5 and 4 over every particle, as the engine runs them.
  void step() {
    const ParticlesView p = view();
    const BondsView b = bonds();
    for (int32_t i = 0; i < p.n; ++i) init_particle<true, false, false, true>(i, p, b, in.materials);
    for (int32_t i = 0; i < p.n; ++i) yield_test(i, p, in.materials);
    for (int32_t i = 0; i < p.n; ++i) state_forces<true, false, false, false>(i, p, b, in.materials, &broke);
  }
};

TEST(Plasticity, BothEndsOfEveryBondFollowTheReturnMappingAndStayMirrored) {
  PlasticBlock blk;
  const Material& m = blk.in.materials.m[0];
  // A shear of 2% (yield strain ~0.3%) with a random part, and an old history mirrored.
  Random rng(11);
  for (size_t i = 0; i < blk.rest.size(); ++i) {
    const Vec4 x = blk.rest[i];
    blk.disp[i] = {real(0.02 * x.y + 2e-6 * (rng.uniform() - 0.5)), real(0.005 * x.z), real(-0.01 * x.x),
                   real(1)};
  }
  for (size_t s = 0; s < blk.plastic.size(); ++s) blk.plastic[s] = real(1e-7 * (rng.uniform() - 0.5));
  for (Vec4& s : blk.state) s.w = real(1);  // particles that have flowed before: their histories are read
  const BondsView b = blk.bonds();
  for (int32_t i = 0; i < b.n; ++i)
    for (int32_t k = 0; k < b.count[i]; ++k) blk.mirror[blk.partner_slot(i, k)] = blk.plastic[b.slot(i, k)];
  const std::vector<real> before = blk.plastic;

  blk.step();

  int yielding = 0;
  for (int32_t i = 0; i < b.n; ++i) {
    const real scale = blk.state[i].w;
    yielding += scale < real(1);
    for (int32_t k = 0; k < b.count[i]; ++k) {
      const int64_t slot = b.slot(i, k);
      const int32_t j = bond_partner(b.neighbor[slot]);
      // The partner's thread wrote this end's e^p at its mirror slot: the same bits.
      ASSERT_EQ(blk.mirror[blk.partner_slot(i, k)], blk.plastic[slot]) << i << " " << k;
      const BondGeometry g = bond_geometry(blk.rest[i], blk.disp[i], blk.rest[j], blk.disp[j]);
      const real expected =
          scale < real(1) ? returned_plastic_extension(g.e, g.r0, blk.state[i].x, scale, before[slot], m)
                          : before[slot];
      ASSERT_EQ(blk.plastic[slot], expected) << i << " " << k;
    }
  }
  EXPECT_GT(yielding, b.n * 9 / 10);

  // Yielding particles end on the yield surface (|t^d| = sqrt(2 psi_0)), the cap aside.
  const real yield_norm = std::sqrt(real(2) * m.yield_psi0);
  for (int32_t i = 0; i < b.n; ++i) {
    if (blk.state[i].w >= real(1)) continue;
    const DilatationPass d = dilatation<false, false, true>(i, blk.view(), b, m);
    EXPECT_NEAR(d.trial_norm, yield_norm, 2e-3 * yield_norm) << i;
  }

  // Both ends see the same t_ij + t_ji: the forces sum to zero.
  double sum[3] = {0, 0, 0}, scale = 0;
  for (const Vec3& f : blk.force) {
    sum[0] += f.x, sum[1] += f.y, sum[2] += f.z;
    scale += length(f);
  }
  for (double s : sum) EXPECT_LT(std::fabs(s), 1e-5 * scale);

  // After a restore the mirror is rebuilt from the history alone: the same bits.
  const std::vector<real> mirrored = blk.mirror;
  std::fill(blk.mirror.begin(), blk.mirror.end(), real(0));
  for (int32_t i = 0; i < b.n; ++i) mirror_plastic(i, b);
  EXPECT_EQ(blk.mirror, mirrored);
}

// A particle that has never flowed carries the mark +infinity in state.w from `plasticity` to the
// next `init` (reads_plastic_history, state_based.h), and `init` and `springforces` then read none
// of its history. On a block sheared more at one end than at the other, where about half the
// particles yield: the marks stay on exactly the particles that never flowed (their histories all
// zero), and after three steps every number has the bits of the same steps with no particle
// marked (every history read).
TEST(Plasticity, ParticlesThatNeverFlowedSkipTheirHistoriesWithTheSameBits) {
  PlasticBlock marked;
  for (const Vec4& s : marked.state) ASSERT_EQ(s.w, real(INFINITY));  // set-up: no plastic extension
  PlasticBlock read_all = marked;
  for (Vec4& s : read_all.state) s.w = real(1);
  const size_t n = marked.rest.size();
  real x_min = marked.rest[0].x, x_max = x_min;
  for (const Vec4& x : marked.rest) x_min = std::min(x_min, x.x), x_max = std::max(x_max, x.x);
  // A shear growing from 0 at one end to `amount` at the other: the far part of the block yields.
  auto shear = [&](PlasticBlock& blk, double amount) {
    for (size_t i = 0; i < n; ++i) {
      const Vec4 x = blk.rest[i];
      blk.disp[i] = {real(amount * (x.x - x_min) / (x_max - x_min) * x.y), 0, 0, real(1)};
    }
  };
  std::vector<bool> flowed(n, false);
  for (double amount : {0.002, 0.0025, 0.003}) {
    shear(marked, amount);
    shear(read_all, amount);
    marked.step();
    read_all.step();
    for (size_t i = 0; i < n; ++i) flowed[i] = flowed[i] || marked.state[i].w < real(1);
  }
  const BondsView b = marked.bonds();
  size_t never = 0;
  for (int32_t i = 0; i < b.n; ++i) {
    if (flowed[size_t(i)]) {
      EXPECT_NE(marked.state[size_t(i)].w, real(INFINITY)) << i;
      EXPECT_EQ(marked.state[size_t(i)].w, read_all.state[size_t(i)].w) << i;
      continue;
    }
    ++never;
    EXPECT_EQ(marked.state[size_t(i)].w, real(INFINITY)) << i;
    EXPECT_EQ(read_all.state[size_t(i)].w, real(1)) << i;
    for (int32_t k = 0; k < b.count[i]; ++k) EXPECT_EQ(marked.plastic[size_t(b.slot(i, k))], real(0)) << i;
  }
  EXPECT_GT(never, n / 5);
  EXPECT_LT(never, n * 4 / 5);
  for (size_t i = 0; i < n; ++i) {
    const Vec4 a = marked.state[i], c = read_all.state[i];
    ASSERT_TRUE(a.x == c.x && a.y == c.y && a.z == c.z) << i;
    const Vec3 f = marked.force[i], g = read_all.force[i];
    ASSERT_TRUE(f.x == g.x && f.y == g.y && f.z == g.z) << i;
  }
  EXPECT_EQ(marked.plastic, read_all.plastic);
  EXPECT_EQ(marked.mirror, read_all.mirror);
}

// The history's load (bond.h plastic_at): a lattice bond of a particle without plastic extension
// takes 0 without reading (an empty view here: a read would fail), a listed bond loads its slot.
TEST(Plasticity, LatticeBondsOfParticlesWithoutHistoryReadNone) {
  std::vector<real> history{real(0.25)};
  const ArrayView<real> one = view_of(history), none{};
  EXPECT_EQ(plastic_at(one, 0, true, LatticeBondGeometry{}), real(0.25));
  EXPECT_EQ(plastic_at(none, 5, false, LatticeBondGeometry{}), real(0));
  EXPECT_EQ(plastic_at(one, 0, false, BondGeometry{}), real(0.25));
  EXPECT_EQ(plastic_at(one, 0, true, BondGeometry{}), real(0.25));
}

TEST(Plasticity, YieldTestKeepsElasticParticlesAndScalesYieldingOnes) {
  Material m;
  m.plastic = 1;
  m.yield_psi0 = real(8);  // yield norm 4
  EXPECT_EQ(yield_scale(real(3), m), real(1));
  EXPECT_EQ(yield_scale(real(4), m), real(1));
  EXPECT_FLOAT_EQ(yield_scale(real(8), m), real(0.5));
  // yield_test: a particle that has never flowed (the norm's sign bit) keeps its mark unless it
  // yields; one that has keeps the factor 1.
  testing::ParticleArrays one;
  one.state.assign(1, Vec4{0, 0, 0, 0});
  one.material.assign(1, 0);
  MaterialTable table;
  table.count = 1;
  table.m[0] = m;
  const std::pair<real, real> cases[] = {{-real(0), real(INFINITY)},
                                         {-real(3), real(INFINITY)},
                                         {real(3), real(1)},
                                         {-real(8), real(0.5)},
                                         {real(8), real(0.5)}};
  for (const auto& [trial, expected] : cases) {
    one.state[0].w = trial;
    yield_test(0, one.view(), table);
    EXPECT_EQ(one.state[0].w, expected) << trial;
  }
  // Chen's cap: |e^p| <= gamma |xi|.
  m.plastic_limit = real(0.01);
  EXPECT_FLOAT_EQ(returned_plastic_extension(real(1), real(2), real(0), real(0.5), real(0), m), real(0.02));
  EXPECT_FLOAT_EQ(returned_plastic_extension(real(-1), real(2), real(0), real(0.5), real(0), m), real(-0.02));
  // Without it: e^d - s (e^d - e^p), e^d = e - theta |xi| / 3.
  m.plastic_limit = 0;
  EXPECT_FLOAT_EQ(returned_plastic_extension(real(0.3), real(1), real(0.3), real(0.25), real(0.1), m),
                  real(0.2 - 0.25 * 0.1));
}

}  // namespace
}  // namespace pd
