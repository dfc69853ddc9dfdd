// SIGINT / SIGTERM under an InterruptGuard (host/io/interrupt.h): recorded, not fatal; the stop
// points of a set-up (StageClock laps) throw Interrupted then, those of a clock made without them
// do not; with the guard gone nothing is left recorded.
#include "host/io/interrupt.h"

#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <vector>

#include "host/geometry/stage_time.h"

namespace pd {
namespace {

TEST(Interrupt, ASignalUnderTheGuardStopsAtTheNextStopPoint) {
  {
    const InterruptGuard guard;
    EXPECT_EQ(InterruptGuard::signal_received(), 0);
    EXPECT_NO_THROW(throw_if_interrupted("nothing"));
    std::vector<StageTime> stages;
    StageClock clock(&stages), quiet(&stages, false);
    clock.lap("before");
    ASSERT_EQ(std::raise(SIGTERM), 0);  // (the process goes on: the guard's handler records it)
    EXPECT_EQ(InterruptGuard::signal_received(), SIGTERM);
    EXPECT_NO_THROW(quiet.lap("after, no stop point"));
    try {
      clock.lap("after");
      FAIL() << "the lap did not stop";
    } catch (const Interrupted& e) {
      EXPECT_EQ(std::string(e.what()), "interrupted during set-up (SIGTERM)");
    }
    EXPECT_EQ(stages.size(), 3u);  // (the stage that ended is recorded before the stop)
  }
  EXPECT_EQ(InterruptGuard::signal_received(), 0);
  EXPECT_NO_THROW(throw_if_interrupted("after the guard"));
}

}  // namespace
}  // namespace pd
