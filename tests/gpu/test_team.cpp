// Teams of threads per particle on the GPU (cuda/team.h): a team summing one particle's bonds
// add the same terms as one thread in another order, so a run with teams follows the run with one
// thread per particle within float round-off and breaks the same bonds; two runs with teams are
// bit-identical. Skipped where no GPU answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "tests/support/broken_bonds.h"
#include "tests/support/fixtures.h"
#include "tests/support/require_gpu.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

double released_energy(Engine& e) {
  EngineSnapshot s;
  e.save(s);
  double sum = 0;
  for (const Ledger& l : s.ledger) sum += l.released;
  return sum;
}

// `in` run `steps` steps with one thread per particle and twice with teams of each size a run
// may take (4 to 32 lanes).
void expect_teams_follow_one_thread(SimulationInput in, int64_t steps) {
  in.bond_threads = 1;
  auto single = make_cuda_engine(in);
  single->advance(steps);
  ParticleState a;
  single->read_state(a);
  const auto broken_single = testing::broken_bond_set(*single);
  const double released_single = released_energy(*single);
  ASSERT_GT(broken_single.size(), 100u) << "the bar must break";
  for (int threads : {4, 8, 16, 32}) {
    SCOPED_TRACE(threads);
    in.bond_threads = threads;
    auto team = make_cuda_engine(in), again = make_cuda_engine(in);
    team->advance(steps);
    again->advance(steps);
    ParticleState b, c;
    team->read_state(b);
    again->read_state(c);
    // The displacement after the halves flew apart: float round-off (~1e-7 per step) grown over
    // the steps, as between the CPU and the GPU (test_equivalence.cpp), far below the 1e-3 allowed
    // there.
    double num = 0, den = 0;
    for (size_t i = 0; i < a.disp.size(); ++i) {
      num += length_squared(b.disp[i] - a.disp[i]);
      den += length_squared(a.disp[i]);
    }
    const double rel = std::sqrt(num / den);
    const auto broken_team = testing::broken_bond_set(*team);
    const double jaccard = testing::jaccard(broken_single, broken_team);
    const double released_team = released_energy(*team);
    std::printf(
        "[ teams of %2d ] %zu particles, %lld steps: displacement rel L2 %.3e, broken %zu / %zu, "
        "Jaccard %.5f, released %.6e / %.6e J\n",
        threads, a.disp.size(), (long long)steps, rel, broken_single.size(), broken_team.size(), jaccard,
        released_single, released_team);
    EXPECT_LT(rel, 1e-4);
    EXPECT_GT(jaccard, 0.98);
    EXPECT_NEAR(released_team, released_single, 1e-3 * released_single);
    EXPECT_TRUE(testing::same_bits(b.disp, c.disp)) << "two runs with teams";
    EXPECT_TRUE(testing::same_bits(b.force, c.force)) << "two runs with teams";
    EXPECT_EQ(broken_team, testing::broken_bond_set(*again));
  }
}

TEST(GpuTeam, BondBasedLatticeFamilies) {
  REQUIRE_GPU();
  expect_teams_follow_one_thread(
      testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4), 32, kLambda, 2), 200);
}

TEST(GpuTeam, BondBasedListedFamiliesOnJitteredParticles) {
  REQUIRE_GPU();
  // Jittered: no lattice families, every partner read from its list.
  expect_teams_follow_one_thread(
      testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4, 0.2), 32, kLambda, 2), 200);
}

TEST(GpuTeam, WeakenedBonds) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 4e-4), 32, kLambda, 2);
  testing::weaken_plane(in, 16 * kLambda, 0.5);
  expect_teams_follow_one_thread(in, 200);
}

TEST(GpuTeam, StateBasedChenCriterionAndStretch) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, false), 32, kLambda, 2);
  expect_teams_follow_one_thread(in, 200);
  in.materials.m[0].chen_fracture = 0;
  expect_teams_follow_one_thread(in, 200);
}

// Plastic lattice families: the lattice loop's teams that read histories walk each word in one
// run from the lane's first entry (bond.h kLatticeRunBits).
TEST(GpuTeam, StateBasedPlasticLattice) {
  REQUIRE_GPU();
  expect_teams_follow_one_thread(
      testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, true), 32, kLambda, 2), 200);
}

TEST(GpuTeam, StateBasedPlasticListed) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, true), 32, kLambda, 2);
  in.lattice_families = false;
  expect_teams_follow_one_thread(in, 200);
}

// Runs `in` 200 steps on two engines made with the environment's `var` at `first` and at
// `second` (null: unset) and expects the same bits and broken bonds, the bar breaking.
void expect_the_same_run_with(const SimulationInput& in, const char* var, const char* first,
                              const char* second) {
  auto make = [&](const char* value) {
    if (value)
      setenv(var, value, 1);
    else
      unsetenv(var);
    auto engine = make_cuda_engine(in);
    unsetenv(var);
    engine->advance(200);
    return engine;
  };
  auto one = make(first), other = make(second);
  ParticleState a, b;
  one->read_state(a);
  other->read_state(b);
  const auto broken = testing::broken_bond_set(*one);
  EXPECT_GT(broken.size(), 100u) << "the bar must break";
  EXPECT_TRUE(testing::same_bits(a.disp, b.disp));
  EXPECT_TRUE(testing::same_bits(a.force, b.force));
  EXPECT_EQ(broken, testing::broken_bond_set(*other));
}

// Bond-based team launches over explicit families visit the particles longest family first
// within each slice (bond_threads.h balanced_particle_order); a particle's sums are its own, so
// the run gives the bits of the launch in index order (PERIFRAC_BALANCE_WINDOW=0), bonds
// breaking, weakened or not.
TEST(GpuTeam, BalancedOrderGivesTheBitsOfTheIndexOrder) {
  REQUIRE_GPU();
  auto bond = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4, 0.2), 32, kLambda, 2);
  auto weak = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 4e-4, 0.2), 32, kLambda, 2);
  testing::weaken_plane(weak, 16 * kLambda, 0.5);
  for (SimulationInput* in : {&bond, &weak})
    for (int threads : {4, 8}) {
      SCOPED_TRACE(threads);
      in->bond_threads = threads;
      expect_the_same_run_with(*in, "PERIFRAC_BALANCE_WINDOW", "0", nullptr);
    }
}

// Team launches in blocks of 128 threads (team.h team_block_for) give the bits of blocks of 256:
// the blocks decide only where each team runs.
TEST(GpuTeam, BlocksOf128GiveTheBitsOfBlocksOf256) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4, 0.2), 32, kLambda, 2);
  for (int threads : {4, 8}) {
    SCOPED_TRACE(threads);
    in.bond_threads = threads;
    expect_the_same_run_with(in, "PERIFRAC_TEAM_BLOCK", "256", "128");
  }
}

// The screened and breaking passes give the same bits with teams too (cuda/kernels/bond_screen.h).
TEST(GpuTeam, ScreenModesAgree) {
  REQUIRE_GPU();
  const testing::EngineFactory gpu = [](const SimulationInput& in) { return make_cuda_engine(in); };
  auto bond = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4), 32, kLambda, 2);
  auto plastic = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, true), 32, kLambda, 2);
  testing::weaken_plane(plastic, 16 * kLambda, 0.5);
  for (SimulationInput* in : {&bond, &plastic})
    for (int threads : {4, 8, 32}) {
      SCOPED_TRACE(threads);
      in->bond_threads = threads;
      testing::expect_screen_modes_agree(gpu, *in, 200);
    }
}

}  // namespace
}  // namespace pd
