// Whether a run asks for CUDA graphs of the step (cuda/engine/step_graphs.h): through its input or
// the environment, else below kGraphParticles particles; the CPU backend runs no graphs and a bad
// value is refused on it too. The graphs' bits: tests/gpu/test_step_graphs.cpp.
#include "cuda/engine/step_graphs.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "cuda/engine/engine.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

TEST(StepGraphs, ARunAsksThroughItsInputOrTheEnvironment) {
  SimulationInput in;
  EXPECT_EQ(requested_step_graphs(in), StepGraphs::kAuto);
  setenv("PERIFRAC_STEP_GRAPHS", "off", 1);
  EXPECT_EQ(requested_step_graphs(in), StepGraphs::kOff);
  setenv("PERIFRAC_STEP_GRAPHS", "on", 1);
  EXPECT_EQ(requested_step_graphs(in), StepGraphs::kOn);
  in.step_graphs = StepGraphs::kOff;
  EXPECT_EQ(requested_step_graphs(in), StepGraphs::kOff);  // the input's own choice wins
  in.step_graphs = StepGraphs::kAuto;
  for (const char* bad : {"yes", "1", "ON", " on"}) {
    setenv("PERIFRAC_STEP_GRAPHS", bad, 1);
    try {
      requested_step_graphs(in);
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("PERIFRAC_STEP_GRAPHS='" + std::string(bad) + "'"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("allowed are auto"), std::string::npos) << e.what();
    }
  }
  unsetenv("PERIFRAC_STEP_GRAPHS");
}

TEST(StepGraphs, LeftToTheEngineSmallScenesTakeThem) {
  SimulationInput in;
  in.particles = testing::lattice_block(16, 16, 16, kLambda, 1e-4).particles;  // 4,096
  EXPECT_TRUE(step_graphs_wanted(in));
  in.step_graphs = StepGraphs::kOff;
  EXPECT_FALSE(step_graphs_wanted(in));
  in.step_graphs = StepGraphs::kAuto;
  in.particles = testing::lattice_block(128, 64, 64, kLambda, 1e-4).particles;  // 524,288
  EXPECT_FALSE(step_graphs_wanted(in));
  in.step_graphs = StepGraphs::kOn;
  EXPECT_TRUE(step_graphs_wanted(in));
}

TEST(StepGraphs, TheCpuRunsNoneAndRefusesABadValue) {
  auto in = testing::lattice_block(8, 8, 8, kLambda, 1e-4);
  in.step_graphs = StepGraphs::kOn;
  auto engine = make_cpu_engine(in);
  engine->advance(40);
  EXPECT_EQ(engine->graphed_steps(), 0);
  EXPECT_EQ(engine->force_passes(), 41);
  in.step_graphs = StepGraphs::kAuto;
  setenv("PERIFRAC_STEP_GRAPHS", "sometimes", 1);
  EXPECT_THROW(make_cpu_engine(in), std::invalid_argument);
  unsetenv("PERIFRAC_STEP_GRAPHS");
}

}  // namespace
}  // namespace pd
