// The screened force passes on the GPU (cuda/kernels/bond_screen.h): runs screened in every
// pass, in none, or as the engine chooses give the same bits, as on the CPU
// (tests/cuda/test_bond_screen.cpp), with one thread per particle (teams: test_team.cpp). Skipped
// where no GPU answers.
#include <gtest/gtest.h>

#include "tests/support/fixtures.h"
#include "tests/support/require_gpu.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

const testing::EngineFactory kGpu = [](const SimulationInput& in) {
  SimulationInput one_thread = in;
  one_thread.bond_threads = 1;
  return make_cuda_engine(one_thread);
};

TEST(GpuBondScreen, BondBasedRunsTheSameInEveryMode) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4), 32, kLambda, 2);
  testing::expect_screen_modes_agree(kGpu, in, 200);
  in.lattice_families = false;
  testing::expect_screen_modes_agree(kGpu, in, 200);
}

TEST(GpuBondScreen, WeakenedBondsRunTheSameInEveryMode) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 4e-4), 32, kLambda, 2);
  testing::weaken_plane(in, 16 * kLambda, 0.5);
  testing::expect_screen_modes_agree(kGpu, in, 200);
}

TEST(GpuBondScreen, StateBasedRunsTheSameInEveryMode) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, false), 32, kLambda, 2);
  testing::expect_screen_modes_agree(kGpu, in, 200);
  in.materials.m[0].chen_fracture = 0;
  testing::expect_screen_modes_agree(kGpu, in, 200);
}

TEST(GpuBondScreen, PlasticRunsTheSameInEveryMode) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, true), 32, kLambda, 2);
  testing::weaken_plane(in, 16 * kLambda, 0.5);
  testing::expect_screen_modes_agree(kGpu, in, 200);
}

}  // namespace
}  // namespace pd
