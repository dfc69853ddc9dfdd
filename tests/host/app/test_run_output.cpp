// A run's frames written on a thread of their own while the engine steps on (host/app/run.cpp,
// RunOutput::write_frame) give the files of frames written before stepping on
// (PERIFRAC_OUTPUT_THREAD=0), bit for bit, checkpoints and the fragment outputs included; a bad
// value of the variable is one error line before any work; the run reports where its loop's time went.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

class RunOutputThread : public testing::TempDirTest {
 protected:
  // Runs the twisted bar (pre-cracked anchors, fragments, a checkpoint every 2 frames) with the
  // variable set to `value`; returns the exit code.
  int run(const std::string& value, const std::string& out) {
    const std::string command = "PERIFRAC_OUTPUT_THREAD=" + value + " " + PERIFRAC_BINARY +
                                " run " PERIFRAC_SOURCE_DIR
                                "/scenes/chen_bar_twist.toml --backend cpu --scale 0.1 --frames 5 "
                                "--checkpoint-every 2 --out " +
                                out + " > " + out + ".log 2>&1";
    return WEXITSTATUS(std::system(command.c_str()));
  }
};

TEST_F(RunOutputThread, WritesTheFilesOfTheSerialOrder) {
  ASSERT_EQ(run("0", path("serial")), 0) << testing::read_all(path("serial.log"));
  ASSERT_EQ(run("1", path("threaded")), 0) << testing::read_all(path("threaded.log"));
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(path("serial"))) {
    const std::string name = e.path().filename().string();
    if (name.rfind("run.", 0) == 0) continue;  // lock, manifest and journal: bookkeeping
    names.insert(name);
    ASSERT_TRUE(fs::exists(path("threaded") + "/" + name)) << name;
    EXPECT_EQ(testing::read_all(e.path().string()), testing::read_all(path("threaded") + "/" + name)) << name;
  }
  EXPECT_TRUE(names.count("frame_00005.pfr"));
  EXPECT_TRUE(names.count("checkpoint.pck"));
  EXPECT_TRUE(names.count("fragments.csv"));
  // The progress lines come in frame order, each frame once.
  const std::string log = testing::read_all(path("threaded.log"));
  size_t at = 0;
  for (int f = 1; f <= 5; ++f) {
    const size_t next = log.find("frame " + std::to_string(f) + "/5", at);
    ASSERT_NE(next, std::string::npos) << "frame " << f << "\n" << log;
    at = next;
  }
}

// The run ends with its frame loop's split: the parts are measured, none negative, and they add up
// to the loop's wall time within what lies between them (the progress line, the loop's own work).
TEST_F(RunOutputThread, EndsWithTheFrameLoopSplit) {
  ASSERT_EQ(run("1", path("split")), 0) << testing::read_all(path("split.log"));
  const std::string log = testing::read_all(path("split.log"));
  const size_t at = log.find("frame loop ");
  ASSERT_NE(at, std::string::npos) << log;
  double total = 0, ratio = 0, steps = 0, drain = 0, read = 0, checks = 0, checkpoints = 0;
  ASSERT_EQ(std::sscanf(log.c_str() + at,
                        "frame loop %lf s (%lf times the stepping): stepping %lf s, waiting for the output "
                        "thread %lf s, frames read back %lf s, checks and energy %lf s, checkpoints %lf s",
                        &total, &ratio, &steps, &drain, &read, &checks, &checkpoints),
            7)
      << log.substr(at, 300);
  EXPECT_GT(steps, 0);
  for (double part : {drain, read, checks, checkpoints}) EXPECT_GE(part, 0);
  EXPECT_GT(checkpoints, 0);  // a checkpoint every 2 frames
  // Each of the six figures is printed to 0.01 s, so the parts' sum and the total may each be off
  // by up to half of that per figure: 0.03 s between them.
  const double parts = steps + drain + read + checks + checkpoints, rounding = 6 * 0.005;
  EXPECT_LE(parts, total + rounding);
  EXPECT_GE(parts, 0.9 * total - rounding);
  EXPECT_NEAR(ratio, total / steps, 0.01 * ratio + 0.01);
}

TEST_F(RunOutputThread, BadValueIsRefusedBeforeTheWork) {
  EXPECT_EQ(run("yes", path("bad")), 2);
  const std::string log = testing::read_all(path("bad.log"));
  EXPECT_NE(log.find("error: PERIFRAC_OUTPUT_THREAD='yes' (allowed: 0 or 1)"), std::string::npos) << log;
  EXPECT_EQ(log.find("particles"), std::string::npos) << "no set-up before the refusal\n" << log;
}

}  // namespace
}  // namespace pd
