// The threads per particle a run uses (cuda/engine/bond_threads.h): how a run asks for a count,
// and the choice from the whole run's particles (regular box grids against explicit families).
#include "cuda/engine/bond_threads.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/team.h"
#include "cuda/views.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

TEST(BondThreads, ARunAsksThroughItsInputOrTheEnvironment) {
  SimulationInput in;
  EXPECT_EQ(requested_bond_threads(in), 0);
  setenv("PERIFRAC_BOND_THREADS", "8", 1);
  EXPECT_EQ(requested_bond_threads(in), 8);
  in.bond_threads = 32;
  EXPECT_EQ(requested_bond_threads(in), 32);  // the input's own count wins
  in.bond_threads = 0;
  for (const char* bad : {"2", "7", "64", "x", "-1", "008"}) {
    setenv("PERIFRAC_BOND_THREADS", bad, 1);
    try {
      requested_bond_threads(in);
      ADD_FAILURE() << bad << " threads accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("PERIFRAC_BOND_THREADS='" + std::string(bad) + "'"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("allowed are 1, 4, 8, 16, 32"), std::string::npos) << e.what();
    }
  }
  unsetenv("PERIFRAC_BOND_THREADS");
}

TEST(BondThreads, ChosenFromTheParticleCountAndTheFamilies) {
  // 24 x 24 x 24 = 13,824 particles: a box grid gets 16 lanes, the same particles jittered (no
  // longer a grid: explicit families) too; 48 x 32 x 32 = 49,152: 4 on the grid, 8 jittered.
  SimulationInput grid;
  grid.particles = testing::lattice_block(24, 24, 24, kLambda, 1e-4).particles;
  EXPECT_EQ(bond_threads_of(grid), 16);
  grid.particles = testing::lattice_block(48, 32, 32, kLambda, 1e-4).particles;
  EXPECT_EQ(bond_threads_of(grid), 4);
  SimulationInput jittered;
  jittered.particles = testing::lattice_block(48, 32, 32, kLambda, 1e-4, 0.2).particles;
  EXPECT_EQ(bond_threads_of(jittered), 8);
  // A box grid run with explicit families (--explicit-families) stays regular: its families are
  // as even as the lattice's.
  grid.lattice_families = false;
  EXPECT_EQ(bond_threads_of(grid), 4);
  grid.bond_threads = 1;
  EXPECT_EQ(bond_threads_of(grid), 1);
}

// Team launches in blocks of 128 where bond-based teams walk short mesh-filled families, else
// 256; the environment forces a size, and names what it allows where it is bad.
TEST(BondThreads, TeamBlockFromTheFamiliesOrTheEnvironment) {
  unsetenv("PERIFRAC_TEAM_BLOCK");
  SimulationInput grid, jittered;
  grid.particles = testing::lattice_block(16, 16, 16, kLambda, 1e-4).particles;
  jittered.particles = testing::lattice_block(16, 16, 16, kLambda, 1e-4, 0.2).particles;
  EXPECT_EQ(team_block_of(jittered, false, 75, 4), 128);   // the vase's families, 19 bonds a lane
  EXPECT_EQ(team_block_of(jittered, false, 531, 8), 128);  // the torus's at 8 lanes, 66 a lane
  EXPECT_EQ(team_block_of(jittered, false, 531, 4), 256);  // at 4 lanes, 133 a lane
  EXPECT_EQ(team_block_of(jittered, false, 4 * kShortLaneBonds, 4), 256);  // at the bound
  EXPECT_EQ(team_block_of(jittered, true, 75, 8), 256);                    // state-based
  EXPECT_EQ(team_block_of(grid, false, 75, 4), 256);                       // a box grid's even families
  setenv("PERIFRAC_TEAM_BLOCK", "128", 1);
  EXPECT_EQ(team_block_of(grid, true, 531, 4), 128);
  setenv("PERIFRAC_TEAM_BLOCK", "0", 1);
  EXPECT_EQ(team_block_of(jittered, false, 75, 4), 128);
  for (const char* bad : {"64", "512", "x", "-128", "1280"}) {
    setenv("PERIFRAC_TEAM_BLOCK", bad, 1);
    try {
      team_block_of(jittered, false, 75, 4);
      ADD_FAILURE() << bad << " threads per block accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("PERIFRAC_TEAM_BLOCK='" + std::string(bad) + "'"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("allowed are 128, 256"), std::string::npos) << e.what();
    }
  }
  unsetenv("PERIFRAC_TEAM_BLOCK");
}

TEST(BondThreads, BalancedOrderSortsEachWindowLongestFamilyFirst) {
  const std::vector<int32_t> count = {3, 9, 9, 1, 5, 7, 2, 8, 4, 6};
  EXPECT_TRUE(balanced_particle_order(count, 0).empty());
  EXPECT_TRUE(balanced_particle_order(count, 1).empty());
  // Windows [0, 4), [4, 8), [8, 10): longest first, ties by index.
  EXPECT_EQ(balanced_particle_order(count, 4), (std::vector<int32_t>{1, 2, 0, 3, 7, 5, 4, 6, 9, 8}));
  const std::vector<int32_t> whole = balanced_particle_order(count, 64);
  EXPECT_EQ(whole, (std::vector<int32_t>{1, 2, 7, 5, 9, 4, 8, 0, 6, 3}));
}

TEST(BondThreads, BalanceWindowFromTheEnvironment) {
  unsetenv("PERIFRAC_BALANCE_WINDOW");
  EXPECT_EQ(balance_window(), kSliceWidth);
  setenv("PERIFRAC_BALANCE_WINDOW", "0", 1);
  EXPECT_EQ(balance_window(), 0);
  setenv("PERIFRAC_BALANCE_WINDOW", "256", 1);
  EXPECT_EQ(balance_window(), 256);
  for (const char* bad : {"x", "-1", "1e3", "12345678"}) {
    setenv("PERIFRAC_BALANCE_WINDOW", bad, 1);
    EXPECT_THROW(balance_window(), std::invalid_argument) << bad;
  }
  unsetenv("PERIFRAC_BALANCE_WINDOW");
}

}  // namespace
}  // namespace pd
