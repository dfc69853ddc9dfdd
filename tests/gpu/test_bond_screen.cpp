// The screened force passes on the GPU (cuda/kernels/bond_screen.h): runs screened in every
// pass, in none, or as the engine chooses give the same bits, as on the CPU
// (tests/cuda/test_bond_screen.cpp), with one thread per particle (teams: test_team.cpp). Skipped
// where no GPU answers.
#include <gtest/gtest.h>

#include "cuda/engine/material.h"
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

// Listed families with the surface correction's factors (partial volumes folded in), as tets and
// Voronoi cells run, with one thread and with teams of 4: the screened and the breaking loops round
// a bond's elongation alike (cuda/vec3.h pinned_dot; nvcc had fused a different product into
// |y| + |xi| in each, bench/NOTES.md "The vase's impact on the GPU").
TEST(GpuBondScreen, ListedBondsWithSurfaceFactorsRunTheSameInEveryMode) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4, 0.3), 32, kLambda, 2);
  in.lattice_families = false;
  Material& m = in.materials.m[0];
  m.surface_correction = 1;
  m.axial_sum = real(lattice_family_sums(m).axial_sum);
  testing::expect_screen_modes_agree(kGpu, in, 200);
  const testing::EngineFactory teams = [](const SimulationInput& run) {
    SimulationInput four = run;
    four.bond_threads = 4;
    return make_cuda_engine(four);
  };
  testing::expect_screen_modes_agree(teams, in, 200);
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
