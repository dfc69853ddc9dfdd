// The engine on the CPU-reference backend: families, conservation, breaking, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "cuda/engine/engine.h"
#include "cuda/engine/frame_reads.h"
#include "cuda/engine/motion.h"
#include "cuda/exec_cpu.h"
#include "cuda/kernels/collisions.h"
#include "cuda/kernels/family.h"
#include "tests/support/fixtures.h"
#include "tests/support/frame_reads.h"
#include "tests/support/same_state.h"

namespace pd {
namespace {

using testing::lattice_block;
using testing::state_block;

// Family of each particle as a sorted list, from the sliced-ELL storage.
std::vector<std::vector<int32_t>> families(Engine& e) {
  BondLists b;
  e.read_bonds(b);
  const BondsView v = b.view();
  std::vector<std::vector<int32_t>> out(b.count.size());
  for (int32_t i = 0; i < v.n; ++i) {
    for (int32_t k = 0; k < v.count[i]; ++k) out[i].push_back(bond_partner(v.neighbor[v.slot(i, k)]));
    std::sort(out[i].begin(), out[i].end());
  }
  return out;
}

// O(N^2) reference: same body, distance at most the family radius (with the same slack).
std::vector<std::vector<int32_t>> brute_force_families(const SimulationInput& in) {
  const auto& ps = in.particles;
  std::vector<std::vector<int32_t>> out(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    const double radius = double(in.materials.m[ps.material[i]].family_radius());
    for (size_t j = 0; j < ps.size(); ++j) {
      if (i == j || ps.body[i] != ps.body[j]) continue;
      const double dx = double(ps.rest[j].x) - ps.rest[i].x, dy = double(ps.rest[j].y) - ps.rest[i].y,
                   dz = double(ps.rest[j].z) - ps.rest[i].z;
      const double reach = family_reach(radius, ps.rest[i], ps.rest[j]);
      if (dx * dx + dy * dy + dz * dz <= reach * reach) out[i].push_back(int32_t(j));
    }
  }
  return out;
}

// A state-based body of one particle has no family (m = 0): it moves without force, its state
// finite, where 1/m once made its dilatation and energy NaN.
TEST(Engine, StateBasedParticleWithoutFamilyStaysFinite) {
  SimulationInput in = testing::state_block(1, 1, 1, 1e-3, 0.5, false);
  in.particles.velocity[0] = {1, 0, 0};
  auto e = make_cpu_engine(in);
  e->advance(5);
  EXPECT_LT(e->first_non_finite(), 0);
  const Energy energy = e->energy();
  EXPECT_TRUE(std::isfinite(energy.balance()));
  EXPECT_EQ(energy.strain, 0.0);
  EXPECT_GT(energy.kinetic, 0.0);
}

// delta = 3 lambda: 122 neighbours within delta; 178 whose cubes overlap the horizon sphere
// (distance <= delta + lambda/2) with partial volumes.

TEST(EngineFamilies, LatticeInteriorNeighbourCounts) {
  for (bool partial : {false, true}) {
    auto in = lattice_block(9, 9, 9, 1e-3);
    in.materials.m[0].partial_volumes = partial;
    auto e = make_cpu_engine(in);
    const auto fam = families(*e);
    const size_t expected = partial ? 178 : 122;
    EXPECT_EQ(fam[4 + 9 * (4 + 9 * 4)].size(), expected);  // centre particle
    EXPECT_EQ(e->family_stats().max, int32_t(expected));
    EXPECT_EQ(fam, brute_force_families(in));
  }
}

// Lattice points at exactly the horizon are partners wherever the body sits: the same block half a
// metre from the origin (its float positions rounded at that magnitude, 1e-5 of delta; a relative
// slack of 1e-6 alone dropped such bonds) has the families it has at the origin.
TEST(EngineFamilies, HorizonPointsKeptFarFromTheOrigin) {
  SimulationInput near = lattice_block(9, 9, 9, 1e-3);
  near.materials.m[0].partial_volumes = false;
  SimulationInput far = near;
  for (size_t i = 0; i < far.particles.size(); ++i) {
    const Vec3 x = near.particles.rest[i];
    far.particles.rest[i] = {real(0.5 + double(x.x)), real(0.3 + double(x.y)), real(-0.4 + double(x.z))};
  }
  auto at_origin = make_cpu_engine(near), away = make_cpu_engine(far);
  EXPECT_EQ(families(*away), families(*at_origin));
  EXPECT_EQ(away->family_stats().max, 122);
  EXPECT_EQ(families(*away), brute_force_families(far));
}

// A frame's read-back goes into the caller's memory when its size holds (a run reads every frame;
// fresh memory each time cost more than the copy), and reads what a fresh read reads.
TEST(EngineReadBack, KeepsTheCallersMemory) {
  auto e = make_cpu_engine(lattice_block(6, 5, 4, 1e-3));
  BondLists bonds;
  ParticleState state;
  e->read_bonds(bonds);
  e->read_state(state);
  const int32_t* neighbor = bonds.neighbor.data();
  const Vec3* disp = state.disp.data();
  e->advance(3);
  e->read_bonds(bonds);
  e->read_state(state);
  EXPECT_EQ(bonds.neighbor.data(), neighbor);
  EXPECT_EQ(state.disp.data(), disp);
  BondLists fresh_bonds;
  ParticleState fresh_state;
  e->read_bonds(fresh_bonds);
  e->read_state(fresh_state);
  EXPECT_EQ(bonds.neighbor, fresh_bonds.neighbor);
  EXPECT_EQ(bonds.count, fresh_bonds.count);
  ASSERT_EQ(state.disp.size(), fresh_state.disp.size());
  for (size_t i = 0; i < state.disp.size(); ++i) {
    EXPECT_EQ(state.disp[i].x, fresh_state.disp[i].x);
    EXPECT_EQ(state.vel[i].z, fresh_state.vel[i].z);
  }
}

// update_bonds keeps a frame's bonds as a whole read would give them, from one bit per slot,
// while bonds break, and across a restore to an earlier state (bonds whole again).
TEST(EngineReadBack, UpdatedBondsAreTheWholeRead) {
  const SimulationInput in = testing::pulled_apart(lattice_block(16, 8, 8, 1e-3, 2e-4), 16, 1e-3, 2);
  auto e = make_cpu_engine(in);
  BondLists kept, whole;
  EngineSnapshot early;
  e->update_bonds(kept);
  e->advance(30);
  e->save(early);
  for (int frame = 0; frame < 4; ++frame) {
    e->advance(40);
    e->update_bonds(kept);
    e->read_bonds(whole);
    ASSERT_EQ(kept.neighbor, whole.neighbor) << "after frame " << frame;
  }
  ASSERT_GT(e->broken_bonds(), 0) << "the run must break bonds";
  e->restore(early);
  e->update_bonds(kept);
  e->read_bonds(whole);
  EXPECT_EQ(kept.neighbor, whole.neighbor) << "after the restore";
  EXPECT_EQ(kept.count, whole.count);
}

// Bond changes taken frame by frame and applied later, in order, to a copy of the bonds as built
// give each frame's whole read (the output threads apply them frames behind the engine).
TEST(EngineReadBack, BondChangesAppliedLaterGiveEachFramesBonds) {
  const SimulationInput in = testing::pulled_apart(lattice_block(16, 8, 8, 1e-3, 2e-4), 16, 1e-3, 2);
  auto e = make_cpu_engine(in);
  BondChanges built;
  e->bond_changes(std::numeric_limits<size_t>::max(), built);
  ASSERT_TRUE(built.whole);
  BondLists behind = built.bonds;
  std::vector<BondChanges> changes(5);
  std::vector<BondLists> whole(5);
  for (int frame = 0; frame < 5; ++frame) {
    e->advance(40);
    e->bond_changes(behind.neighbor.size(), changes[size_t(frame)]);
    EXPECT_FALSE(changes[size_t(frame)].whole) << "frame " << frame;
    e->read_bonds(whole[size_t(frame)]);
  }
  ASSERT_NE(whole.front().neighbor, whole.back().neighbor) << "the run must break bonds between frames";
  for (int frame = 0; frame < 5; ++frame) {
    changes[size_t(frame)].apply_to(behind);
    ASSERT_EQ(behind.neighbor, whole[size_t(frame)].neighbor) << "frame " << frame;
  }
}

// Frames taken while bonds break and finished after the engine stepped on (the output threads'
// read-back) are the reads made at once at their steps; seven frames, more than the read slots.
TEST(EngineReadBack, FramesFinishedLaterAreTheReadsAtTheirSteps) {
  const SimulationInput in = testing::pulled_apart(lattice_block(16, 8, 8, 1e-3, 2e-4), 16, 1e-3, 2);
  testing::expect_frames_read_later_as_read_at_once([&] { return make_cpu_engine(in); }, 7, 40);
}

// The read slots: four out at most, fewer where they would hold more than their bytes allow (one
// always), a slot given back is taken again; once page-locked memory is refused, none.
TEST(EngineReadBack, SlotsAreBoundedInCountAndBytes) {
  CpuExec exec(nullptr);
  FrameReadSlots<CpuExec> slots;
  std::vector<std::unique_ptr<FrameReadSlots<CpuExec>::Slot>> out;
  for (int k = 0; k < 4; ++k) out.push_back(slots.take(exec, 1000));
  for (const auto& s : out) ASSERT_NE(s, nullptr);
  EXPECT_EQ(slots.take(exec, 1000), nullptr);
  slots.give_back(std::move(out.back()));
  out.pop_back();
  auto again = slots.take(exec, 1000);
  ASSERT_NE(again, nullptr);
  EXPECT_GE(again->bytes, 1000u);
  slots.give_back(std::move(again));
  for (auto& s : out) slots.give_back(std::move(s));
  // With 3000 bytes allowed: two slots of 1001, one of 5000.
  FrameReadSlots<CpuExec> small(3000);
  auto a = small.take(exec, 1001), b = small.take(exec, 1001);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(small.take(exec, 1001), nullptr);
  small.give_back(std::move(a));
  small.give_back(std::move(b));
  auto big = small.take(exec, 5000);
  ASSERT_NE(big, nullptr);
  EXPECT_EQ(small.take(exec, 5000), nullptr);
  small.give_back(std::move(big));

  struct RefusingExec {
    struct ReadEvent {
      void wait() const {}
    };
    void* allocate_host(size_t) { throw std::runtime_error("refused"); }
    static void release_host(void*) {}
  } refusing;
  FrameReadSlots<RefusingExec> none;
  EXPECT_EQ(none.take(refusing, 1000), nullptr);
  EXPECT_EQ(none.take(refusing, 1000), nullptr);
}

// The set-up's stages, in the order they run, each timed; pre-cracks and the state-based
// set-up only where the run has them.
TEST(EngineSetup, ReportsItsStagesInOrder) {
  std::vector<std::string> names;
  auto stage_names = [&](const SimulationInput& in) {
    const auto start = std::chrono::steady_clock::now();
    const auto engine = make_cpu_engine(in);
    const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<std::string> out;
    double sum = 0;
    for (const SetupStage& s : engine->setup_stages()) {
      out.push_back(s.name);
      EXPECT_GE(s.seconds, 0) << s.name;
      sum += s.seconds;
    }
    EXPECT_LE(sum, whole);
    return out;
  };
  EXPECT_EQ(stage_names(lattice_block(6, 5, 4, 1e-3)),
            (std::vector<std::string>{"upload", "families", "surface correction", "lattice tables",
                                      "stable step", "first forces"}));
  SimulationInput cracked = state_block(6, 5, 4, 1e-3, 1e-3, false);
  cracked.cuts = {CutTriangle{{{{2.5e-3, -1, -1}, {2.5e-3, 1, -1}, {2.5e-3, 0, 1}}}, 0, -1}};
  EXPECT_EQ(stage_names(cracked),
            (std::vector<std::string>{"upload", "families", "surface correction", "pre-cracks",
                                      "lattice tables", "stable step", "state-based", "first forces"}));
}

TEST(EngineFamilies, RandomPointsMatchBruteForce) {
  auto in = lattice_block(10, 8, 7, 1e-3, 1e-3, 0.9, 11);
  // A second body overlapping the first: no bonds between bodies.
  for (size_t i = 0; i < in.particles.size(); i += 3) in.particles.body[i] = 1;
  auto e = make_cpu_engine(in);
  EXPECT_EQ(families(*e), brute_force_families(in));
  const FamilyStats& s = e->family_stats();
  EXPECT_GT(s.min, 0);
  EXPECT_LE(s.bonds, s.slots);
}

// Runs `in` with random velocities of standard deviation `speed` and contact on: bonds break,
// and the total momentum stays within round-off of the start (no external force).
void expect_momentum_conserved(SimulationInput in, double speed, uint64_t seed) {
  Random rng(seed);
  for (auto& v : in.particles.velocity)
    v = {real(speed * rng.normal()), real(speed * rng.normal()), real(speed * rng.normal())};
  in.contact = true;
  in.step.contact_stiffness = real(1e8);
  double scale = 0;
  const auto p0 = testing::total_momentum(in, in.particles.velocity, &scale);
  auto e = make_cpu_engine(in);
  e->advance(300);
  ParticleState s;
  e->read_state(s);
  EXPECT_GT(e->broken_bonds(), 0);
  const auto p1 = testing::total_momentum(in, s.vel);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(p1[a], p0[a], 64 * std::numeric_limits<real>::epsilon() * scale) << "axis " << a;
}

TEST(EngineConservation, MomentumIsConservedWithoutExternalForces) {
  expect_momentum_conserved(lattice_block(8, 6, 5, 1e-3, 5e-4, 0.2), 1.0, 3);
}

// The same with the state-based plastic material, damage-weighted fracture on.
TEST(EngineConservation, MomentumIsConservedWithPlasticityAndDamage) {
  expect_momentum_conserved(testing::state_block(8, 6, 5, 1e-3, 5e-4, true, 0.2), 3.0, 4);
}

TEST(EngineBreaking, NoStateBasedBondBreaksAtRest) {
  for (bool plastic : {false, true}) {
    auto e = make_cpu_engine(testing::state_block(6, 6, 6, 1e-3, 1e-5, plastic));
    e->advance(100);
    EXPECT_EQ(e->broken_bonds(), 0);
    ParticleState s;
    e->read_state(s);
    for (const Vec3& u : s.disp) EXPECT_LT(length(u), 1e-12);
  }
}

// Every broken bond is broken from both ends.
TEST(EngineBreaking, BondsBreakSymmetrically) {
  auto in = lattice_block(12, 4, 4, 1e-3, 2e-4);
  // Pull the two halves apart.
  for (size_t i = 0; i < in.particles.size(); ++i)
    in.particles.velocity[i] = {real(in.particles.rest[i].x < 6e-3 ? -2 : 2), 0, 0};
  auto e = make_cpu_engine(in);
  e->advance(200);
  BondLists b;
  e->read_bonds(b);
  const BondsView v = b.view();
  std::set<std::pair<int32_t, int32_t>> broken;
  int64_t total = 0;
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t nb = v.neighbor[v.slot(i, k)];
      total += 1;
      if (!bond_intact(nb)) broken.insert({i, bond_partner(nb)});
    }
  ASSERT_GT(broken.size(), 0u);
  for (const auto& [i, j] : broken) EXPECT_TRUE(broken.count({j, i})) << i << "-" << j;
  EXPECT_EQ(int64_t(broken.size()), e->broken_bonds());
  EXPECT_LT(int64_t(broken.size()), total);
}

// Chen's damage factor alpha raises the limit of damaged material (eq. 18 as the paper's text
// means it): a framed brittle plate punched by a projectile sheds far fewer loose particles (all
// bonds broken) with alpha = 8 than with alpha = 0.
TEST(EngineBreaking, DamageFactorLeavesFewerLooseParticles) {
  auto punch = [](double alpha) {
    auto in = testing::state_block(20, 20, 3, 1e-3, 1e-3, false);
    in.materials.m[0].damage_alpha = real(alpha);
    for (size_t i = 0; i < in.particles.size(); ++i) {
      const Vec3 r = in.particles.rest[i];
      if (std::min({r.x, r.y, 19e-3f - r.x, 19e-3f - r.y}) < 1.5e-3f) in.particles.flags[i] |= kAnchored;
    }
    in.step.n_projectiles = 1;
    in.step.projectile[0] = {
        {real(9.5e-3), real(9.5e-3), real(6.5e-3)}, {0, 0, real(-40)}, real(3e-3), real(1e8)};
    auto e = make_cpu_engine(in);
    e->advance(1200);
    ParticleState s;
    e->read_state(s);
    const auto loose = std::count(s.intact.begin(), s.intact.end(), 0);
    std::printf("  alpha %g: %ld loose particles, %ld broken bonds\n", alpha, long(loose),
                long(e->broken_bonds()));
    return int64_t(loose);
  };
  const int64_t loose0 = punch(0), loose8 = punch(8);  // 215 and 32 (eq. 18 as printed: 312)
  ASSERT_GT(loose0, 50);
  EXPECT_LT(loose8, loose0 / 3);
}

TEST(EngineBreaking, NoBondBreaksAtRest) {
  auto in = lattice_block(6, 6, 6, 1e-3, 1e-4);
  auto e = make_cpu_engine(in);
  e->advance(100);
  EXPECT_EQ(e->broken_bonds(), 0);
  ParticleState s;
  e->read_state(s);
  for (const Vec3& u : s.disp) EXPECT_LT(length(u), 1e-12);
}

TEST(EngineDeterminism, TwoRunsAreBitIdentical) {
  auto in = lattice_block(8, 8, 4, 1e-3, 3e-4, 0.3);
  Random rng(5);
  for (auto& v : in.particles.velocity) v = {real(rng.normal()), real(rng.normal()), real(rng.normal())};
  in.contact = true;
  in.step.contact_stiffness = real(1e8);
  ParticleState a, b;
  for (ParticleState* s : {&a, &b}) {
    auto e = make_cpu_engine(in);
    e->advance(150);
    e->read_state(*s);
  }
  ASSERT_EQ(a.disp.size(), b.disp.size());
  for (size_t i = 0; i < a.disp.size(); ++i) {
    EXPECT_EQ(a.disp[i].x, b.disp[i].x);
    EXPECT_EQ(a.disp[i].y, b.disp[i].y);
    EXPECT_EQ(a.disp[i].z, b.disp[i].z);
  }
}

// A cloud of unbonded particles (each its own body) flying through each other: after every few
// steps the force on each particle is, to the last bit, the sum of Levine's eq. 6 over every
// other particle in ascending order, although the contact lists were built only now and then.
// With a contact spacing of 3 lambda the lists outgrow their first room and are built again.
// few_fast: the cloud drifts at 1 m/s but for every 40th particle at 60 m/s, so that the builds
// are set off by a few particles at a time, whose lists are rebuilt alone (contact_relist.h).
// drift, gravity: a velocity every particle has besides, and a gravity; then the lists are kept in
// the frame that moves with the cloud (contact_frame.h).
void expect_list_forces_equal_all_pairs(double contact_spacing, double stiffness, bool few_fast = false,
                                        ContactRebuild rebuild = ContactRebuild::kIncremental,
                                        Vec3 drift = {0, 0, 0}, real gravity = 0) {
  auto in = lattice_block(8, 8, 8, 1e-3, 1e-3, 0.9, 13);
  in.materials.m[0].contact_spacing = real(contact_spacing);
  Random rng(29);
  for (size_t i = 0; i < in.particles.size(); ++i) {
    in.particles.body[i] = int32_t(i);
    const double speed = !few_fast ? 30 : i % 40 == 0 ? 60 : 1;
    in.particles.velocity[i] =
        Vec3{real(speed * rng.normal()), real(speed * rng.normal()), real(speed * rng.normal())} + drift;
  }
  in.contact = true;
  in.contact_rebuild = rebuild;
  in.step.contact_stiffness = real(stiffness);
  in.step.gravity = {0, -gravity, 0};
  auto e = make_cpu_engine(in);
  const real rc = real(0.5) * in.materials.m[0].contact_spacing;
  int checked = 0, touching = 0;
  const int rounds = few_fast ? 60 : 30;
  for (int round = 0; round < rounds; ++round) {
    e->advance(7);
    ParticleState s;
    e->read_state(s);
    std::vector<Vec3> x(s.disp.size());
    for (size_t i = 0; i < x.size(); ++i) x[i] = in.particles.rest[i] + s.disp[i];
    std::vector<Vec3> contact(x.size(), Vec3{0, 0, 0});
    for (size_t i = 0; i < x.size(); ++i)
      for (size_t j = 0; j < x.size(); ++j)
        if (j != i) contact[i] += contact_force(x[i], x[j], rc, in.step.contact_stiffness);
    // The weight, added after the contact force: the force on a particle that touches nothing
    // (the particles' masses are equal).
    Vec3 weight{0, 0, 0};
    for (size_t i = 0; i < x.size(); ++i)
      if (contact[i].x == 0 && contact[i].y == 0 && contact[i].z == 0) weight = s.force[i];
    for (size_t i = 0; i < x.size(); ++i) {
      const Vec3 f = contact[i] + weight;
      ASSERT_EQ(s.force[i].x, f.x) << "particle " << i << " after " << e->step() << " steps";
      ASSERT_EQ(s.force[i].y, f.y);
      ASSERT_EQ(s.force[i].z, f.z);
      touching += contact[i].x != 0 || contact[i].y != 0 || contact[i].z != 0;
      ++checked;
    }
  }
  EXPECT_GT(touching, few_fast ? 0 : checked / 20);  // contacts were there to find
  // Every list built at the start and again now and then, not every step; in between, the lists
  // of the particles that left their skins rebuilt alone (relisted), in most steps: each particle
  // sets off its own rebuild, where a full build starts every skin afresh.
  const int64_t builds = e->stats().entry("pd/contact_build").launches;
  const int64_t relisted = e->stats().entry("pd/contact_relist").launches;
  std::printf("  %lld full builds, %lld rounds of relisting in %lld steps\n", (long long)builds,
              (long long)relisted, (long long)e->step());
  EXPECT_GT(builds + relisted, 3);
  EXPECT_LT(builds, 7 * rounds / 3);
  EXPECT_LE(builds + relisted, 7 * rounds + 1);
  if (few_fast && rebuild == ContactRebuild::kIncremental) {
    EXPECT_GT(relisted, 3 * builds);  // most rounds rebuilt the movers' lists alone
  }
  if (rebuild == ContactRebuild::kFull) {
    EXPECT_EQ(relisted, 0);
  }
  if (drift.x != 0) {  // at rest every particle would leave its skin every 32 steps
    EXPECT_LT(builds, 3);
  }
}

TEST(EngineContact, ListForcesEqualTheSumOverAllPairs) {
  expect_list_forces_equal_all_pairs(1e-3, 1e8);
}

TEST(EngineContact, ListsThatOutgrowTheirRoomAreBuiltAgain) {
  expect_list_forces_equal_all_pairs(3e-3, 1e6);
}

TEST(EngineContact, MoversListsRebuiltAloneGiveTheForcesOfAllPairs) {
  expect_list_forces_equal_all_pairs(1e-3, 1e8, true);
  expect_list_forces_equal_all_pairs(3e-3, 1e6, true);  // partners' lists outgrow their room
}

TEST(EngineContact, FullBuildsGiveTheForcesOfAllPairs) {
  expect_list_forces_equal_all_pairs(1e-3, 1e8, true, ContactRebuild::kFull);
}

// The cloud of the few fast movers flying at 200 m/s under a gravity of 2e5 m/s^2 (it travels 10
// spacings, and falls farther than a skin at rest, in the run): its lists are kept in the frame
// that moves with it, built once or twice where at rest all of them would leave their skins every
// 32 steps, and give the forces of all pairs to the last bit, the relisted movers' too.
TEST(EngineContact, ListsInAMovingFrameGiveTheForcesOfAllPairs) {
  expect_list_forces_equal_all_pairs(1e-3, 1e8, true, ContactRebuild::kIncremental, {200, 0, 0}, real(2e5));
  expect_list_forces_equal_all_pairs(1e-3, 1e8, true, ContactRebuild::kFull, {0, 0, -200}, real(2e5));
}

// A body flying apart leaves all its skins at once, in the frame at rest and in the moving one
// alike: more movers than a relisting round keeps (max(256, n / 512)), so every build is a full
// one, with no round tried first. The same body in free fall keeps its lists in the moving frame
// (contact_frame.h): built once.
TEST(EngineContact, ACrowdOfMoversGoesStraightToTheFullBuild) {
  for (const bool bursting : {true, false}) {
    auto in = lattice_block(8, 8, 8, 1e-3);  // out of contact with each other
    for (size_t i = 0; i < in.particles.size(); ++i) {
      in.particles.body[i] = int32_t(i);
      const Vec3 out = in.particles.rest[i] - Vec3{real(3.5e-3), real(3.5e-3), real(3.5e-3)};
      in.particles.velocity[i] = bursting ? (real(30) / length(out)) * out : Vec3{0, 0, real(-30)};
    }
    in.contact = true;
    in.step.contact_stiffness = real(1e8);
    in.step.gravity = {0, 0, real(-9.81)};
    auto e = make_cpu_engine(in);
    e->advance(200);
    const int64_t builds = e->stats().entry("pd/contact_build").launches;
    if (bursting)
      EXPECT_GT(builds, 3);  // the skins were left again and again
    else
      EXPECT_EQ(builds, 1);
    EXPECT_EQ(e->stats().entry("pd/contact_relist").launches, 0);
  }
}

// The same run with the movers' lists rebuilt alone and with every list built at every build:
// bit for bit the same state.
TEST(EngineContact, RelistingAndFullBuildsRunTheSameBits) {
  ParticleState a, b;
  for (auto [rebuild, s] :
       {std::pair{ContactRebuild::kIncremental, &a}, std::pair{ContactRebuild::kFull, &b}}) {
    auto in = lattice_block(10, 10, 10, 1e-3, 1e-3, 0.9, 17);
    Random rng(31);
    for (size_t i = 0; i < in.particles.size(); ++i) {
      in.particles.body[i] = int32_t(i);
      const double speed = i % 50 == 0 ? 80 : 2;
      in.particles.velocity[i] = {real(speed * rng.normal()), real(speed * rng.normal()),
                                  real(speed * rng.normal())};
    }
    in.contact = true;
    in.contact_rebuild = rebuild;
    in.step.contact_stiffness = real(1e8);
    auto e = make_cpu_engine(in);
    e->advance(600);
    e->read_state(*s);
    EXPECT_GT(e->energy().contact + 1, 1);
  }
  testing::expect_same_particles(a, b);
}

// PERIFRAC_CONTACT_REBUILD names what it allows.
TEST(EngineContact, ABadContactRebuildSettingIsNamed) {
  setenv("PERIFRAC_CONTACT_REBUILD", "sometimes", 1);
  auto in = lattice_block(3, 3, 3, 1e-3);
  in.contact = true;
  try {
    make_cpu_engine(in);
    ADD_FAILURE() << "a bad PERIFRAC_CONTACT_REBUILD was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("PERIFRAC_CONTACT_REBUILD='sometimes'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("incremental"), std::string::npos) << e.what();
  }
  unsetenv("PERIFRAC_CONTACT_REBUILD");
}

// An intact lattice (neighbours at lambda, lists reaching 0.9 lambda) has empty lists: built
// once, and `collisions` never launched while nothing moves.
TEST(EngineContact, AnIntactLatticeAtRestBuildsOnceAndSkipsCollisions) {
  auto in = lattice_block(6, 6, 6, 1e-3);
  in.contact = true;
  in.step.contact_stiffness = real(1e8);
  auto e = make_cpu_engine(in);
  e->advance(50);
  EXPECT_EQ(e->stats().entry("pd/contact_build").launches, 1);
  EXPECT_EQ(e->stats().entry("pd/collisions").launches, 0);
  EXPECT_EQ(e->energy().contact, 0);
}

// A moving grip: anchored particles follow their prescribed velocity exactly.
TEST(EngineAnchors, MovingAnchorsFollowTheirVelocity) {
  auto in = lattice_block(10, 4, 4, 1e-3, 1.0);
  for (size_t i = 0; i < in.particles.size(); ++i)
    if (in.particles.rest[i].x > 8.5e-3) {
      in.particles.flags[i] |= kAnchored;
      in.particles.velocity[i] = {real(0.5), 0, 0};
    }
  auto e = make_cpu_engine(in);
  e->advance(400);
  ParticleState s;
  e->read_state(s);
  const double travelled = 400 * double(in.step.dt) * 0.5;
  for (size_t i = 0; i < s.disp.size(); ++i)
    if (in.particles.flags[i] & kAnchored) {
      EXPECT_NEAR(s.disp[i].x, travelled, 1e-5 * travelled);
      EXPECT_EQ(s.vel[i].x, real(0.5));
    }
  EXPECT_GT(s.disp[0].x, 0);  // the free end is pulled along through the bonds
}

// A scripted anchor turns and translates its particles rigidly: each one sits at
// P + offset + R (X - P) with the velocity of that motion, to float round-off.
TEST(EngineAnchors, ScriptedAnchorMovesItsParticlesRigidly) {
  auto in = lattice_block(6, 6, 6, 1e-3);
  AnchorScript script;
  script.pivot = {3e-3, 3e-3, 3e-3};
  script.omega = {0, 200, 100};  // rad/s: about 1.5 degrees over the run
  script.path = {{0, 0, 0, 0}, {1e-4, 1e-4, 0, 0}, {1e-3, 1e-4, -2e-4, 0}};
  in.motion.anchors = {AnchorScript{}, script};
  for (size_t i = 0; i < in.particles.size(); ++i)
    if (in.particles.rest[i].y < 2e-3) {
      in.particles.flags[i] |= kAnchored;
      in.particles.anchor[i] = 1;
    }
  auto e = make_cpu_engine(in);
  e->advance(1000);
  ParticleState s;
  e->read_state(s);
  const double t = e->time();
  const auto rm = rotation_minus_identity(script.omega, t);
  const PathSample move = sample_path(script.path, t);
  int checked = 0;
  for (size_t i = 0; i < s.disp.size(); ++i) {
    if (!(in.particles.flags[i] & kAnchored)) continue;
    const double d[3] = {in.particles.rest[i].x - script.pivot[0], in.particles.rest[i].y - script.pivot[1],
                         in.particles.rest[i].z - script.pivot[2]};
    const double u[3] = {s.disp[i].x, s.disp[i].y, s.disp[i].z}, v[3] = {s.vel[i].x, s.vel[i].y, s.vel[i].z};
    double r[3];  // R d
    for (int row = 0; row < 3; ++row)
      r[row] = d[row] + rm[size_t(3 * row)] * d[0] + rm[size_t(3 * row + 1)] * d[1] +
               rm[size_t(3 * row + 2)] * d[2];
    const auto& w = script.omega;
    const double spin[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(u[c], move.position[size_t(c)] + r[c] - d[c], 1e-9) << i;  // 1e-6 of the 1 mm spacing
      EXPECT_NEAR(v[c], move.velocity[size_t(c)] + spin[c], 1e-6) << i;
    }
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

// From its release time on an anchor lets go: its particles fall with the rest.
TEST(EngineAnchors, ReleasedAnchorLetsGo) {
  auto in = lattice_block(4, 4, 4, 1e-3);
  in.step.gravity = {0, real(-9.81), 0};
  AnchorScript hold;
  hold.release = 100.5 * double(in.step.dt);
  in.motion.anchors = {hold};
  for (size_t i = 0; i < in.particles.size(); ++i) in.particles.flags[i] |= kAnchored;
  auto e = make_cpu_engine(in);
  ParticleState s;
  e->advance(100);
  e->read_state(s);
  for (const Vec3& v : s.vel) EXPECT_EQ(length(v), 0);
  e->advance(100);
  e->read_state(s);
  const double fall = 9.81 * 100 * double(in.step.dt);  // speed gained after the release
  for (const Vec3& v : s.vel) EXPECT_NEAR(v.y, -fall, 1e-3 * fall);
}

TEST(EngineAnchors, AnchoredParticlesStayPut) {
  auto in = lattice_block(6, 6, 6, 1e-3);
  in.step.gravity = {0, real(-9.81), 0};
  for (size_t i = 0; i < in.particles.size(); ++i)
    if (in.particles.rest[i].y < 0.5e-3) in.particles.flags[i] |= kAnchored;
  auto e = make_cpu_engine(in);
  e->advance(200);
  ParticleState s;
  e->read_state(s);
  for (size_t i = 0; i < s.disp.size(); ++i) {
    if (in.particles.flags[i] & kAnchored) {
      EXPECT_EQ(length(s.disp[i]), 0);
      EXPECT_EQ(length(s.vel[i]), 0);
    } else if (in.particles.rest[i].y > 4.5e-3) {
      EXPECT_LT(s.disp[i].y, 0);  // the free top sags under gravity
    }
  }
}

}  // namespace
}  // namespace pd
