// Teams of threads per particle (cuda/team.h): which scenes get them, how a run asks for a count,
// which entries a lane visits, and that the CPU backend, which runs one thread per particle,
// gives the same bits whatever a run asks for. The teams' sums on the GPU: tests/gpu/test_team.cpp.
#include "cuda/team.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>

#include "tests/support/fixtures.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

TEST(Team, ScenesBelowTheThresholdGetAWarpPerParticle) {
  EXPECT_EQ(bond_threads_for(3840, 0), 32);
  EXPECT_EQ(bond_threads_for(kTeamParticles - 1, 0), 32);
  EXPECT_EQ(bond_threads_for(kTeamParticles, 0), 1);
  EXPECT_EQ(bond_threads_for(3840, 1), 1);
  EXPECT_EQ(bond_threads_for(1000000, 32), 32);
}

TEST(Team, ARunAsksThroughItsInputOrTheEnvironment) {
  SimulationInput in;
  EXPECT_EQ(requested_bond_threads(in), 0);
  setenv("PERIFRAC_BOND_THREADS", "1", 1);
  EXPECT_EQ(requested_bond_threads(in), 1);
  in.bond_threads = 32;
  EXPECT_EQ(requested_bond_threads(in), 32);  // the input's own count wins
  in.bond_threads = 0;
  setenv("PERIFRAC_BOND_THREADS", "8", 1);
  try {
    requested_bond_threads(in);
    ADD_FAILURE() << "8 threads accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("PERIFRAC_BOND_THREADS='8'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("allowed are 1, 32"), std::string::npos) << e.what();
  }
  unsetenv("PERIFRAC_BOND_THREADS");
}

TEST(Team, ALaneVisitsEveryEntryATeamWidthApart) {
  EXPECT_EQ((Team<32>{5, ~0u}.own_bits()), 1u << 5);
  EXPECT_EQ((Team<8>{3, 0xffu}.own_bits()), 0x08080808u);
  EXPECT_EQ((Team<2>{1, 0x3u}.own_bits()), 0xaaaaaaaau);
  EXPECT_EQ(Team<1>::own_bits(), ~0u);
  // One thread's "team" sums nothing but itself.
  EXPECT_EQ(Team<1>::sum(real(2.5)), real(2.5));
  EXPECT_EQ(Team<1>::max(real(-1)), real(-1));
}

TEST(Team, TheCpuBackendRunsOneThreadWhateverTheRunAsks) {
  auto in = testing::pulled_apart(testing::lattice_block(16, 8, 8, 1e-3, 2e-4), 16, 1e-3, 2);
  in.bond_threads = 1;
  auto one = make_cpu_engine(in);
  in.bond_threads = 32;
  auto asked = make_cpu_engine(in);
  one->advance(100);
  asked->advance(100);
  ASSERT_GT(one->broken_bonds(), 0);
  ParticleState a, b;
  one->read_state(a);
  asked->read_state(b);
  EXPECT_TRUE(testing::same_bits(a.disp, b.disp));
  EXPECT_TRUE(testing::same_bits(a.force, b.force));
}

}  // namespace
}  // namespace pd
