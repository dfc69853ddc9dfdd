// A run's frames written on threads of their own while the engine steps on (host/app/run_output.cpp,
// RunOutput::write_frame) give the files of frames written before stepping on
// (PERIFRAC_OUTPUT_THREAD=0), bit for bit, checkpoints and the fragment outputs included; a bad
// value of the variable is one error line before any work; the run reports where its loop's and its
// output threads' time went; a file that cannot be written ends the run after the frames before it.
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
// to the loop's wall time within what lies between them (the progress line, the loop's own work);
// then the output threads' split and the command's wall time.
TEST_F(RunOutputThread, EndsWithTheFrameLoopSplit) {
  ASSERT_EQ(run("1", path("split")), 0) << testing::read_all(path("split.log"));
  const std::string log = testing::read_all(path("split.log"));
  const size_t at = log.find("frame loop ");
  ASSERT_NE(at, std::string::npos) << log;
  double total = 0, ratio = 0, steps = 0, drain = 0, last = 0, read = 0, checks = 0, checkpoints = 0;
  ASSERT_EQ(std::sscanf(log.c_str() + at,
                        "frame loop %lf s (%lf times the stepping): stepping %lf s, waiting for the output "
                        "thread %lf s (the last frames %lf s), frames taken %lf s, checks and energy %lf s, "
                        "checkpoints %lf s",
                        &total, &ratio, &steps, &drain, &last, &read, &checks, &checkpoints),
            8)
      << log.substr(at, 300);
  EXPECT_GT(steps, 0);
  for (double part : {drain, last, read, checks, checkpoints}) EXPECT_GE(part, 0);
  EXPECT_LE(last, drain + 0.01);  // the last frames' wait is part of the whole wait
  EXPECT_GT(checkpoints, 0);      // a checkpoint every 2 frames
  // Each of the six figures is printed to 0.01 s, so the parts' sum and the total may each be off
  // by up to half of that per figure: 0.03 s between them.
  const double parts = steps + drain + read + checks + checkpoints, rounding = 6 * 0.005;
  EXPECT_LE(parts, total + rounding);
  EXPECT_GE(parts, 0.9 * total - rounding);
  EXPECT_NEAR(ratio, total / steps, 0.01 * ratio + 0.01);

  // Then the output threads' own split, over frames 0 to 5.
  const size_t threads_at = log.find("output threads over ");
  ASSERT_NE(threads_at, std::string::npos) << log;
  long long frames = 0;
  double fragment_setup = -1, read_back = -1, analysis = 0, surfaces = 0, longest_analysis = 0, writing = 0,
         longest_writing = 0, fragment_files = 0, frame_files = 0;
  double stage[5] = {-1, -1, -1, -1, -1};  // the analysis's stages
  ASSERT_EQ(
      std::sscanf(log.c_str() + threads_at,
                  "output threads over %lld frames: fragment outputs set up %lf s, frames read back %lf "
                  "s, fragments found %lf s (components %lf, fits %lf, crack mesh %lf, blending %lf, "
                  "statistics %lf s) and crack surfaces taken %lf s on the first (longest frame %lf s), the "
                  "frames written %lf s on the second (longest %lf s; the fragment files %lf s beside the "
                  "frame files %lf s)",
                  &frames, &fragment_setup, &read_back, &analysis, &stage[0], &stage[1], &stage[2], &stage[3],
                  &stage[4], &surfaces, &longest_analysis, &writing, &longest_writing, &fragment_files,
                  &frame_files),
      15)
      << log.substr(threads_at, 500);
  // The stages make up the analysis (each figure to 0.01 s).
  double stage_sum = 0;
  for (const double s : stage) {
    EXPECT_GE(s, 0);
    stage_sum += s;
  }
  EXPECT_LE(stage_sum, analysis + 0.03);
  EXPECT_EQ(frames, 6);
  EXPECT_GE(fragment_setup, 0);
  EXPECT_GE(read_back, 0);
  EXPECT_GT(writing, 0);
  // The longest frame is at most the sum of all and at least the mean (figures to 0.01 s and
  // 0.001 s: each may be off by half of that).
  const double r = 0.005 + 0.0005;
  EXPECT_LE(longest_analysis, analysis + surfaces + 2 * r);
  EXPECT_GE(6 * longest_analysis, analysis + surfaces - 2 * r);
  EXPECT_LE(longest_writing, writing + r);
  EXPECT_GE(6 * longest_writing, writing - r);
  // The fragment files and the frame files are written side by side within a frame's writing.
  EXPECT_LE(fragment_files, writing + 0.01);
  EXPECT_LE(frame_files, writing + 0.01);

  // Last, the command's wall time: the set-up's two parts, the same frame loop and the end-of-run
  // outputs, which cover it but for the lines printed between them.
  const size_t run_at = log.find("run        ");
  ASSERT_NE(run_at, std::string::npos) << log;
  long long frame0 = -1;
  double wall = 0, wall_ratio = 0, setup = 0, engine = 0, outputs = 0, loop = 0, end = 0;
  ASSERT_EQ(
      std::sscanf(log.c_str() + run_at,
                  "run %lf s (%lf times the stepping): set-up %lf s (scene and engine %lf s, outputs to "
                  "frame %lld %lf s), frame loop %lf s, end-of-run outputs %lf s",
                  &wall, &wall_ratio, &setup, &engine, &frame0, &outputs, &loop, &end),
      8)
      << log.substr(run_at, 300);
  EXPECT_EQ(frame0, 0);
  for (double part : {engine, outputs, end}) EXPECT_GE(part, 0);  // (a small scene's set-up prints 0.00)
  EXPECT_NEAR(setup, engine + outputs, 3 * 0.005);
  EXPECT_NEAR(loop, total, 0.01);
  EXPECT_NEAR(wall_ratio, wall / steps, 0.01 * wall_ratio + 0.01);
  const double covered = setup + loop + end;
  EXPECT_LE(covered, wall + 4 * 0.005);
  EXPECT_GE(covered, 0.8 * wall - 4 * 0.005);

  // The set-up's stages, printed before the frame loop: their sum is the set-up but for the lines
  // printed between them; the engine's families and frame 0 among them (or in "others").
  const size_t stages_at = log.find("set-up     ");
  ASSERT_NE(stages_at, std::string::npos) << log;
  double staged = 0;
  ASSERT_EQ(std::sscanf(log.c_str() + stages_at, "set-up %lf s: ", &staged), 1) << log.substr(stages_at, 300);
  const std::string stages = log.substr(stages_at, log.find('\n', stages_at) - stages_at);
  EXPECT_NE(stages.find("others "), std::string::npos) << stages;
  EXPECT_LE(staged, setup + 2 * 0.005) << stages;
  EXPECT_GE(staged, 0.8 * setup - 2 * 0.005) << stages;
}

// A frame's file that cannot be written ends the run with the file's name, a non-zero exit and the
// frames before it complete, whether the files of a frame are written while the next is stepped
// or before: no later frame is written after the failure.
TEST_F(RunOutputThread, AFailedWriteEndsTheRunWithTheFramesBeforeIt) {
  for (const std::string value : {"0", "1"}) {
    const std::string out = path("fail" + value);
    // A folder in the way of frame 3's fragments file: its rename fails.
    fs::create_directories(out + "/fragments_00003.pfg/in_the_way");
    EXPECT_NE(run(value, out), 0) << value;
    const std::string log = testing::read_all(out + ".log");
    EXPECT_NE(log.find("fragments_00003.pfg"), std::string::npos) << value << "\n" << log;
    for (int f = 0; f <= 2; ++f)
      EXPECT_TRUE(fs::exists(out + "/frame_0000" + std::to_string(f) + ".pfr")) << f;
    EXPECT_FALSE(fs::exists(out + "/frame_00004.pfr")) << value;
    EXPECT_FALSE(fs::exists(out + "/frame_00005.pfr")) << value;
  }
}

TEST_F(RunOutputThread, BadValueIsRefusedBeforeTheWork) {
  EXPECT_EQ(run("yes", path("bad")), 2);
  const std::string log = testing::read_all(path("bad.log"));
  EXPECT_NE(log.find("error: PERIFRAC_OUTPUT_THREAD='yes' (allowed: 0 or 1)"), std::string::npos) << log;
  EXPECT_EQ(log.find("particles"), std::string::npos) << "no set-up before the refusal\n" << log;
}

}  // namespace
}  // namespace pd
