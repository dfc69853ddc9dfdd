// Kernel 5, `plasticity`, and the return mapping `springforces` applies to both ends of each bond:
// on a block whose every particle yields, the history stays mirrored bit for bit, each end moves
// as Chen's eqs. 13-15 say, yielding particles end on the yield surface, and forces balance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
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

TEST(Plasticity, YieldTestKeepsElasticParticlesAndScalesYieldingOnes) {
  Material m;
  m.plastic = 1;
  m.yield_psi0 = real(8);  // yield norm 4
  EXPECT_EQ(yield_scale(real(3), m), real(1));
  EXPECT_EQ(yield_scale(real(4), m), real(1));
  EXPECT_FLOAT_EQ(yield_scale(real(8), m), real(0.5));
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
