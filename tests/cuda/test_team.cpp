// Teams of threads per particle (cuda/team.h): which scenes get them, which entries a lane visits,
// and that the CPU backend, which runs one thread per particle, gives the same bits whatever a run
// asks for. The teams' sums on the GPU: tests/gpu/test_team.cpp.
#include "cuda/team.h"

#include <gtest/gtest.h>

#include "tests/support/fixtures.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

TEST(Team, RegularFamiliesGetLanesWhileOneThreadPerParticleLeavesTheGpuIdle) {
  // particles x lanes kept near kTeamThreads, and no team of 2 (one thread is faster there).
  EXPECT_EQ(bond_threads_for(3840, false, 0), 32);
  EXPECT_EQ(bond_threads_for(20196, false, 0), 8);
  EXPECT_EQ(bond_threads_for(51200, false, 0), 4);
  EXPECT_EQ(bond_threads_for(kTeamThreads / 4, false, 0), 4);
  EXPECT_EQ(bond_threads_for(kTeamThreads / 4 + 1, false, 0), 1);
  EXPECT_EQ(bond_threads_for(131072, false, 0), 1);
  EXPECT_EQ(bond_threads_for(16000000, false, 0), 1);
}

TEST(Team, ExplicitFamiliesAlwaysShareTheirBondsOut) {
  EXPECT_EQ(bond_threads_for(3840, true, 0), 32);
  EXPECT_EQ(bond_threads_for(51200, true, 0), 8);
  EXPECT_EQ(bond_threads_for(149118, true, 0), 8);
  EXPECT_EQ(bond_threads_for(kTeamListedEight, true, 0), 4);
  EXPECT_EQ(bond_threads_for(577199, true, 0), 4);
  EXPECT_EQ(bond_threads_for(16000000, true, 0), 4);
}

TEST(Team, ARequestWins) {
  EXPECT_EQ(bond_threads_for(3840, false, 1), 1);
  EXPECT_EQ(bond_threads_for(1000000, true, 32), 32);
  for (int t : {1, 4, 8, 16, 32}) EXPECT_TRUE(valid_bond_threads(t)) << t;
  for (int t : {0, 2, 3, 7, 64}) EXPECT_FALSE(valid_bond_threads(t)) << t;
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
