// `perifrac run` (host/app/run.cpp) with the ghost correction: the stable step is measured on the
// engine at start-up, dt = "auto" takes half of it, and the time-step check holds a scene's dt
// against it (a dt the families' estimate would have refused runs; one past the measured step is
// refused with one line naming simulation.dt).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "host/app/run.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class RunStableStep : public testing::TempDirTest {
 protected:
  // The twisted bar with ghosts at --scale 0.1, set-up only, with `extra` options; the exit code,
  // and the output in `log`.
  int run(const std::string& extra, const std::string& name, std::string& log) {
    const std::string command = std::string(PERIFRAC_BINARY) +
                                " run " PERIFRAC_SOURCE_DIR
                                "/scenes/chen_bar_twist.toml --backend cpu --scale 0.1 --frames 0 "
                                "--set 'materials.rubber.surface_correction=\"ghosts\"' " +
                                extra + " --out " + path(name) + " > " + path(name) + ".log 2>&1";
    const int code = WEXITSTATUS(std::system(command.c_str()));
    log = testing::read_all(path(name) + ".log");
    return code;
  }
};

struct Stability {
  double families = 0, stable = 0, dt = 0, ratio = 0;
};

Stability stability_of(const std::string& log) {
  Stability s;
  const size_t families = log.find("stability  dt_c from the families ");
  const size_t measured = log.find("stability  with ghosts, measured on the engine: stable step ");
  if (families == std::string::npos || measured == std::string::npos) return s;
  std::sscanf(log.c_str() + families, "stability  dt_c from the families %lf", &s.families);
  const size_t dt = log.find("dt = ", measured);
  std::sscanf(log.c_str() + measured, "stability  with ghosts, measured on the engine: stable step %lf",
              &s.stable);
  std::sscanf(log.c_str() + dt, "dt = %lf s is %lf of it", &s.dt, &s.ratio);
  return s;
}

TEST_F(RunStableStep, AutoTakesHalfTheMeasuredStep) {
  std::string log;
  ASSERT_EQ(run("", "auto", log), kExitOk) << log;
  const Stability s = stability_of(log);
  ASSERT_GT(s.stable, 0) << log;
  EXPECT_NEAR(s.ratio, 0.5, 0.005) << log;
  EXPECT_NEAR(s.dt, 0.5 * s.stable, 1e-3 * s.stable);
  // The ghosts' reach escapes the families' sum: the measured step is longer than its estimate.
  EXPECT_GT(s.stable, 1.5 * s.families) << log;
}

TEST_F(RunStableStep, TheCheckHoldsDtAgainstTheMeasuredStep) {
  std::string log;
  ASSERT_EQ(run("", "auto", log), kExitOk) << log;
  const Stability s = stability_of(log);
  ASSERT_GT(s.stable, 0) << log;
  char dt[96];
  // Past the families' estimate, within the measured step: runs.
  std::snprintf(dt, sizeof dt, "--set simulation.dt=%.6g", 0.9 * s.stable);
  EXPECT_EQ(run(dt, "within", log), kExitOk) << log;
  // Past the measured step: one line naming simulation.dt.
  std::snprintf(dt, sizeof dt, "--set simulation.dt=%.6g", 1.05 * s.stable);
  EXPECT_EQ(run(dt, "past", log), kExitUsage) << log;
  EXPECT_NE(log.find("simulation.dt"), std::string::npos) << log;
  EXPECT_NE(log.find("measured on the engine with the ghost correction"), std::string::npos) << log;
}

}  // namespace
}  // namespace pd
