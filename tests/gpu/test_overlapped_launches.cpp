// Overlapped launches (cuda/exec_cuda.cuh, programmatic dependent launch): each kernel waits for
// the one before it at its start, so a run whose launches overlap leaves the bits of the same run
// launched in turn (PERIFRAC_OVERLAP_LAUNCHES=off), step by step and as graphs, through breaking,
// plastic flow and contact. A kernel that read before its wait would race with the launch before
// it and differ here. Skipped where no GPU answers.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

#include "tests/support/fixtures.h"
#include "tests/support/require_gpu.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

// A CUDA engine for `in`, its launches overlapped or in turn (the environment is read when the
// engine is made).
std::unique_ptr<Engine> gpu_engine(const SimulationInput& in, bool overlap) {
  if (overlap)
    unsetenv("PERIFRAC_OVERLAP_LAUNCHES");
  else
    setenv("PERIFRAC_OVERLAP_LAUNCHES", "off", 1);
  auto e = make_cuda_engine(in);
  unsetenv("PERIFRAC_OVERLAP_LAUNCHES");
  return e;
}

void expect_overlap_leaves_the_bits(SimulationInput in, int64_t steps) {
  for (StepGraphs graphs : {StepGraphs::kOff, StepGraphs::kOn}) {
    SCOPED_TRACE(graphs == StepGraphs::kOn ? "graphs" : "launches");
    in.step_graphs = graphs;
    auto in_turn = gpu_engine(in, false), overlapped = gpu_engine(in, true);
    in_turn->advance(steps);
    overlapped->advance(steps);
    ASSERT_GT(in_turn->broken_bonds(), 0) << "the run must break bonds";
    testing::expect_same_run(*in_turn, *overlapped);
  }
}

TEST(GpuOverlappedLaunches, BondBasedRunsTheSameAsLaunchesInTurn) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(32, 16, 16, kLambda, 2e-4), 32, kLambda, 2);
  in.step.gravity = {0, real(-9.81), 0};
  expect_overlap_leaves_the_bits(in, 250);
  in.lattice_families = false;
  expect_overlap_leaves_the_bits(in, 250);
}

TEST(GpuOverlappedLaunches, PlasticRunsTheSameAsLaunchesInTurn) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::state_block(32, 16, 16, kLambda, 2e-4, true), 32, kLambda, 2);
  testing::weaken_plane(in, 16 * kLambda, 0.5);
  expect_overlap_leaves_the_bits(in, 250);
}

// Contact lists put host work between the launches, so both passes of the loop run launches.
TEST(GpuOverlappedLaunches, ContactRunsTheSameAsLaunchesInTurn) {
  REQUIRE_GPU();
  auto in = testing::pulled_apart(testing::lattice_block(16, 16, 16, kLambda, 2e-4), 16, kLambda, 2);
  in.contact = true;
  expect_overlap_leaves_the_bits(in, 250);
}

}  // namespace
}  // namespace pd
