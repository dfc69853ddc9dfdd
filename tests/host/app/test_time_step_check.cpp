// The time-step choices and checks of `perifrac run` and `perifrac bench`
// (host/app/time_step_check.h): dt = "auto" never takes a step the families' check refuses.
#include <gtest/gtest.h>

#include "cuda/engine/engine.h"
#include "host/app/time_step_check.h"
#include "tests/support/fixtures.h"
#include "tests/support/screen_runs.h"

namespace pd {
namespace {

TEST(AutoStep, TakesTheFamiliesStepWhereItIsShorterThanHalfTheContinuumOne) {
  const SimulationInput in = testing::pulled_apart(testing::lattice_block(8, 6, 6, 1e-3), 8, 1e-3, 2);
  auto engine = make_cpu_engine(in);
  const double family = engine->critical_time_step();
  ASSERT_GT(family, 0);
  double dt = 3 * family;  // "auto"'s half of a continuum estimate past the families' step
  EXPECT_TRUE(auto_step_within_families(*engine, true, family, dt));
  EXPECT_EQ(dt, family);
  // Set on the engine: its steps are those of an engine given that step.
  auto reference = make_cpu_engine(in);
  reference->set_time_step(family);
  engine->advance(5);
  reference->advance(5);
  ParticleState a, b;
  engine->read_state(a);
  reference->read_state(b);
  EXPECT_TRUE(testing::same_bits(a.disp, b.disp));
  // Within the families' step, or a scene's own dt: unchanged.
  double within = 0.5 * family, given = 3 * family;
  EXPECT_FALSE(auto_step_within_families(*engine, true, family, within));
  EXPECT_EQ(within, 0.5 * family);
  EXPECT_FALSE(auto_step_within_families(*engine, false, family, given));
  EXPECT_EQ(given, 3 * family);
}

}  // namespace
}  // namespace pd
