// CUDA graphs of the step (cuda/engine/step_graphs.h): a run whose steps go as graphs leaves the
// bits of the same run launched step by step, through breaking, in advances of any length, and
// after a restore; a run with host work between the launches (contact lists) takes none. Skipped
// where no GPU answers.
#include <gtest/gtest.h>

#include <memory>

#include "cuda/engine/step_graphs.h"
#include "tests/support/fixtures.h"
#include "tests/support/require_gpu.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

std::unique_ptr<Engine> gpu_engine(SimulationInput in, StepGraphs graphs) {
  in.step_graphs = graphs;
  return make_cuda_engine(in);
}

// Advances of lengths that split graphs from single steps in several ways.
void advance_unevenly(Engine& e) {
  for (int64_t steps : {1, 45, 32, 100, 7, 64}) e.advance(steps);
}

void expect_graphs_agree(const SimulationInput& in) {
  auto launched = gpu_engine(in, StepGraphs::kOff);
  auto graphed = gpu_engine(in, StepGraphs::kOn);
  advance_unevenly(*launched);
  advance_unevenly(*graphed);
  EXPECT_EQ(launched->graphed_steps(), 0);
  EXPECT_EQ(graphed->graphed_steps(), 7 * kGraphSteps);  // 45: 1, 32: 1, 100: 3, 64: 2
  EXPECT_EQ(launched->force_passes(), graphed->force_passes());
  ASSERT_GT(launched->broken_bonds(), 0) << "the run must break bonds";
  testing::expect_same_run(*launched, *graphed);
}

TEST(GpuStepGraphs, BondBasedRunsTheSameAsLaunched) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4), 32, kLambda, 2);
  in.step.gravity = {0, real(-9.81), 0};
  expect_graphs_agree(in);
  in.lattice_families = false;
  expect_graphs_agree(in);
}

TEST(GpuStepGraphs, StateBasedAndPlasticRunTheSameAsLaunched) {
  REQUIRE_GPU();
  expect_graphs_agree(
      testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, false), 32, kLambda, 2));
  auto plastic = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, true), 32, kLambda, 2);
  testing::weaken_plane(plastic, 16 * kLambda, 0.5);
  expect_graphs_agree(plastic);
}

TEST(GpuStepGraphs, ARestoredRunContinuesTheSame) {
  REQUIRE_GPU();
  const auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4), 32, kLambda, 2);
  auto whole = gpu_engine(in, StepGraphs::kOn);
  whole->advance(100);
  EngineSnapshot half;
  whole->save(half);
  whole->advance(150);
  auto resumed = gpu_engine(in, StepGraphs::kOn);
  resumed->advance(64);  // its graphs recorded before the restore
  resumed->restore(half);
  resumed->advance(150);
  EXPECT_GT(resumed->graphed_steps(), 0);
  testing::expect_same_run(*whole, *resumed);
}

TEST(GpuStepGraphs, HostWorkBetweenLaunchesRunsWithout) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(16, 16, 16, kLambda, 2e-4), 16, kLambda, 2);
  in.contact = true;
  auto e = gpu_engine(in, StepGraphs::kOn);
  e->advance(100);
  EXPECT_EQ(e->graphed_steps(), 0);
}

}  // namespace
}  // namespace pd
