// The integration kernels fused with their neighbours (cuda/kernels/integrate_fused.h,
// IntegrationFusion): which passes a run's steps launch, and that the fused passes give the bits
// of the kernels apart. The GPU's: gpu-check's golden outputs and CPU-vs-GPU equivalence.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/kernels/integrate_fused.h"
#include "tests/support/fixtures.h"
#include "tests/support/particle_arrays.h"
#include "tests/support/same_state.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

// The launches of each kernel over `steps` steps after the set-up (whose first forces are not
// counted).
std::map<std::string, int64_t> launches_over(const SimulationInput& in, int64_t steps) {
  auto e = make_cpu_engine(in);
  e->stats().reset_times();
  e->advance(steps);
  std::map<std::string, int64_t> n;
  for (const auto& [name, s] : e->stats().table())
    if (s.launches > 0) n[name] = s.launches;
  return n;
}

// The launches of every instantiation of `kernel` ("kernel" and "kernel[...]").
int64_t launches_of(const std::map<std::string, int64_t>& n, const std::string& kernel) {
  int64_t sum = 0;
  for (const auto& [name, count] : n)
    if (name == kernel || name.rfind(kernel + "[", 0) == 0) sum += count;
  return sum;
}

SimulationInput falling_block() {
  SimulationInput in = testing::lattice_block(6, 5, 4, kLambda);
  in.step.gravity = {0, real(-9.81), 0};
  return in;
}

TEST(IntegrationFusion, BondBasedStepsMeetInOnePassWithInitAndGravity) {
  const auto n = launches_over(falling_block(), 10);
  EXPECT_EQ(n.at("pd/position_update[init]"), 1);
  EXPECT_EQ(n.at("pd/velocity_position_update[gravity,init]"), 9);
  EXPECT_EQ(n.at("pd/velocity_update[gravity]"), 1);
  EXPECT_EQ(launches_of(n, "pd/init"), 0);
  EXPECT_EQ(launches_of(n, "pd/bodyforces"), 0);
  EXPECT_EQ(launches_of(n, "pd/springforces"), 10);
}

TEST(IntegrationFusion, StateBasedInitAndProjectilesKeepTheirKernels) {
  SimulationInput state = testing::state_block(6, 5, 4, kLambda, 1e-3, false);
  state.step.gravity = {0, real(-9.81), 0};
  auto n = launches_over(state, 10);
  EXPECT_EQ(n.at("pd/position_update"), 1);
  EXPECT_EQ(n.at("pd/velocity_position_update[gravity]"), 9);
  EXPECT_EQ(launches_of(n, "pd/init"), 10);  // the dilatation reads the partners' new positions

  SimulationInput hit = falling_block();
  hit.step.n_projectiles = 1;
  hit.step.projectile[0] = {{real(3e-3), real(8e-3), real(2e-3)}, {0, real(-40), 0}, real(2e-3), real(1e8)};
  n = launches_over(hit, 10);
  EXPECT_EQ(n.at("pd/bodyforces"), 10);  // the projectile reads positions and the time
  EXPECT_EQ(n.at("pd/velocity_position_update[init]"), 9);
  EXPECT_EQ(n.at("pd/velocity_update"), 1);
}

// Scripted motion is host work between two steps: each step ends with its own velocity update.
TEST(IntegrationFusion, ScriptedMotionKeepsTheStepsApart) {
  SimulationInput in = falling_block();
  AnchorScript script;
  script.path = {{0, 0, 0, 0}, {1e-3, 1e-4, 0, 0}};
  in.motion.anchors = {AnchorScript{}, script};
  for (size_t i = 0; i < in.particles.size(); ++i)
    if (in.particles.rest[i].y < 0.5e-3) {
      in.particles.flags[i] |= kAnchored;
      in.particles.anchor[i] = 1;
    }
  const auto n = launches_over(in, 10);
  EXPECT_EQ(n.at("pd/position_update[init]"), 10);
  EXPECT_EQ(n.at("pd/velocity_update[gravity]"), 10);
  EXPECT_EQ(n.count("pd/velocity_position_update[gravity,init]"), 0u);
}

// Steps run as one call (the steps meet) against one call per step (each its own velocity update):
// the same bits, through contact, the floor, held particles and bonds breaking.
void expect_steps_together_as_apart(SimulationInput in, int64_t steps) {
  auto together = make_cpu_engine(in), apart = make_cpu_engine(in);
  together->advance(steps);
  for (int64_t s = 0; s < steps; ++s) apart->advance(1);
  ParticleState a, b;
  together->read_state(a);
  apart->read_state(b);
  testing::expect_same_particles(a, b);
  EXPECT_EQ(a.intact, b.intact);
  EXPECT_EQ(together->broken_bonds(), apart->broken_bonds());
  EXPECT_GT(together->broken_bonds(), 0);
}

SimulationInput dropped_and_torn(SimulationInput in, uint64_t seed) {
  Random rng(seed);
  for (size_t i = 0; i < in.particles.size(); ++i) {
    const Vec3 r = in.particles.rest[i];
    in.particles.velocity[i] = {real(r.x > 4e-3 ? 30 : -30) + real(rng.normal()), real(-3),
                                real(rng.normal())};
    if (r.x < 0.5e-3 && r.y > 3.5e-3) in.particles.flags[i] |= kAnchored;
  }
  in.step.gravity = {0, real(-9.81), 0};
  in.step.floor_enabled = 1;
  in.step.floor_height = real(-2e-5);
  in.step.restitution = real(0.9);
  in.contact = true;
  in.step.contact_stiffness = real(1e8);
  return in;
}

TEST(IntegrationFusion, StepsTogetherGiveTheStepsApartBits) {
  expect_steps_together_as_apart(dropped_and_torn(testing::lattice_block(9, 5, 4, kLambda, 2e-3), 3), 200);
}

TEST(IntegrationFusion, StateBasedPlasticStepsTogetherGiveTheStepsApartBits) {
  expect_steps_together_as_apart(dropped_and_torn(testing::state_block(9, 5, 4, kLambda, 2e-3, true), 4),
                                 200);
}

// The fused passes against the kernels apart, particle by particle, on records that take every
// branch: held particles, particles below the floor moving down, damaged and compressed ones. The
// fused pass holds the force with gravity without storing it (the next force pass writes every
// particle's), and its floor test reads no reference position above the particles' lowest one.
TEST(IntegrationFusion, FusedPassesGiveTheKernelsApartBits) {
  constexpr int kN = 64;
  Random rng(11);
  testing::ParticleArrays a;
  std::vector<int32_t> count(kN);
  std::vector<uint8_t> anchor(kN, 0);
  for (int i = 0; i < kN; ++i) {
    const auto u = [&] { return real(rng.normal()); };
    a.rest.push_back({u() * real(1e-2), u() * real(1e-2), u() * real(1e-2), real(1e-9)});
    a.disp.push_back({u() * real(1e-4), u() * real(1e-4), u() * real(1e-4), real(0)});
    a.state.push_back({0, 0, 0, 0});
    a.vel.push_back({u(), u(), u()});
    a.force.push_back({u() * real(1e-3), u() * real(1e-3), u() * real(1e-3)});
    a.inv_mass.push_back(real(1e6) * (real(1.5) + real(rng.uniform())));
    a.tau0.push_back(real(1e-3));
    a.smin.push_back(u() * real(1e-3));
    a.material.push_back(0);
    a.body.push_back(0);
    count[size_t(i)] = 40;
    a.intact.push_back(int32_t(rng.uniform() * 40));
    a.flags.push_back(i % 7 == 0 ? kAnchored : 0);
    a.ledger.push_back(Ledger{});
  }
  MaterialTable mt;
  mt.count = 1;
  mt.m[0] = testing::glass_material(kLambda);
  mt.m[0].damage_alpha = real(2);
  StepParams sp;
  sp.dt = real(1e-7);
  sp.gravity = {0, real(-9.81), 0};
  sp.floor_enabled = 1;
  sp.floor_height = real(0);
  sp.restitution = real(0.8);
  testing::ParticleArrays b = a;
  StepParams fused = sp;
  fused.lowest_rest_y = real(INFINITY);
  for (const Vec4& x : a.rest) fused.lowest_rest_y = std::min(fused.lowest_rest_y, x.y);
  const auto views = [&](testing::ParticleArrays& arrays) {
    ParticlesView p = arrays.view();
    p.anchor = view_of(anchor);
    BondsView bonds;
    bonds.count = view_of(count);
    return std::make_pair(p, bonds);
  };
  const auto [pa, ba] = views(a);
  const auto [pb, bb] = views(b);
  for (int i = 0; i < kN; ++i) body_forces<false>(i, pa, sp);
  for (int i = 0; i < kN; ++i) velocity_update(i, pa, sp);
  for (int i = 0; i < kN; ++i) position_update<false>(i, pa, sp);
  for (int i = 0; i < kN; ++i) init_particle<false, false, kNoLattice, false>(i, pa, ba, mt);
  for (int i = 0; i < kN; ++i)
    velocity_then_position_update<true, false, true>(i, pb, bb, mt, fused, ContactView{});
  for (int i = 0; i < kN; ++i) {
    const auto same4 = [](Vec4 x, Vec4 y) { return x.x == y.x && x.y == y.y && x.z == y.z && x.w == y.w; };
    const auto same3 = [](Vec3 x, Vec3 y) { return x.x == y.x && x.y == y.y && x.z == y.z; };
    EXPECT_TRUE(same4(a.disp[size_t(i)], b.disp[size_t(i)])) << i;
    EXPECT_TRUE(same3(a.vel[size_t(i)], b.vel[size_t(i)])) << i;
    EXPECT_TRUE(same3(a.force[size_t(i)], force_with_gravity(i, pb, sp))) << i;
    EXPECT_EQ(a.ledger[size_t(i)].work, b.ledger[size_t(i)].work) << i;
  }
  int reflected = 0, raised = 0;  // the branches taken: the floor's, and the raised limits'
  for (int i = 0; i < kN; ++i) {
    reflected += !(a.flags[size_t(i)] & kAnchored) && a.ledger[size_t(i)].work < 0;
    raised += a.disp[size_t(i)].w > real(1e-3);
  }
  EXPECT_GT(reflected, 0);
  EXPECT_GT(raised, 0);
}

}  // namespace
}  // namespace pd
