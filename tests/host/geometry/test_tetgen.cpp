// TetGen as an external program: a run that does not end is stopped, with a message that says
// what TetGen needs, instead of hanging the scene's set-up; a check made beside it that fails stops it,
// and so does an interrupt.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <unistd.h>

#include "host/geometry/shapes.h"
#include "host/geometry/tetgen.h"
#include "host/io/interrupt.h"
#include "tests/support/scoped_env.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

// A `tetgen` that never finishes (or runs `body` instead), first on PATH while the object lives;
// its folder removed after.
class NeverEndingTetgen {
 public:
  explicit NeverEndingTetgen(const std::string& name, const std::string& body = "exec sleep 60")
      : dir_(fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()))),
        old_path_(std::getenv("PATH") ? std::getenv("PATH") : "") {
    fs::create_directories(dir_);
    {
      std::ofstream script(dir_ / "tetgen");
      script << "#!/bin/sh\n" << body << "\n";
    }
    fs::permissions(dir_ / "tetgen", fs::perms::owner_all);
    setenv("PATH", (dir_.string() + ":" + old_path_).c_str(), 1);
  }
  ~NeverEndingTetgen() {
    setenv("PATH", old_path_.c_str(), 1);
    fs::remove_all(dir_);
  }
  std::string work_dir() const { return (dir_ / "work").string(); }  // (a work folder: no cache)

 private:
  fs::path dir_;
  std::string old_path_;
};

// TetGen on a box with `options`: its error message (empty if none) and the seconds it took.
std::pair<std::string, double> tetrahedralize_box(const TetgenOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::string message;
  try {
    tetrahedralize(box_mesh({1, 1, 1}), options, "box.obj");
  } catch (const MeshError& e) {
    message = e.what();
  }
  return {message, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
}

TEST(Tetgen, ARunPastItsTimeIsStoppedWithAMessage) {
  const NeverEndingTetgen tetgen("perifrac-test-tetgen");
  testing::ScopedEnv limit("PERIFRAC_TETGEN_SECONDS", "1");
  TetgenOptions options;
  options.work_dir = tetgen.work_dir();
  const auto [message, seconds] = tetrahedralize_box(options);
  EXPECT_NE(message.find("box.obj"), std::string::npos) << message;
  EXPECT_NE(message.find("was stopped after 1 s"), std::string::npos) << message;
  EXPECT_NE(message.find("shell_thickness"), std::string::npos) << message;
  EXPECT_LT(seconds, 10);
}

// A TetGen that crashes: the signal and its last words, one line.
TEST(Tetgen, ACrashIsReportedWithItsSignal) {
  const NeverEndingTetgen tetgen("perifrac-test-tetgen-crash",
                                 "echo 'Segmentation fault ahead'\nkill -SEGV $$");
  TetgenOptions options;
  options.work_dir = tetgen.work_dir();
  const std::string message = tetrahedralize_box(options).first;
  EXPECT_NE(message.find("crashed (signal 11), its last words: 'Segmentation fault ahead'"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(Tetgen, ABadTimeLimitInTheEnvironmentIsRefused) {
  const NeverEndingTetgen tetgen("perifrac-test-tetgen-limit");
  TetgenOptions options;
  options.work_dir = tetgen.work_dir();
  for (const char* bad : {"abc", "-5", "0", "1s"}) {
    testing::ScopedEnv limit("PERIFRAC_TETGEN_SECONDS", bad);
    try {
      tetrahedralize(box_mesh({1, 1, 1}), options, "box.obj");
      ADD_FAILURE() << bad << " was taken";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("PERIFRAC_TETGEN_SECONDS='" + std::string(bad) + "'"),
                std::string::npos)
          << e.what();
    }
  }
}

// A check that overlaps TetGen (TetgenOptions::while_running, the particle budget found on a
// thread of its own) and fails stops TetGen at once, its own message going on.
TEST(Tetgen, AFailedCheckWhileRunningStopsIt) {
  const NeverEndingTetgen tetgen("perifrac-test-tetgen-check");
  TetgenOptions options;
  options.work_dir = tetgen.work_dir();
  bool checked = false;
  options.while_running = [&] {
    checked = true;
    throw MeshError("box.obj", "over the budget");
  };
  const auto [message, seconds] = tetrahedralize_box(options);
  EXPECT_TRUE(checked);
  EXPECT_NE(message.find("over the budget"), std::string::npos) << message;
  EXPECT_LT(seconds, 10);
}

// Ctrl-C while TetGen runs (here the fake sends SIGINT to perifrac, as a terminal sends it to
// both): TetGen is killed and the set-up stops with Interrupted, not a crash report.
TEST(Tetgen, AnInterruptKillsItAndStopsTheSetUp) {
  const NeverEndingTetgen tetgen("perifrac-test-tetgen-interrupted", "kill -INT $PPID\nexec sleep 60");
  const InterruptGuard guard;
  TetgenOptions options;
  options.work_dir = tetgen.work_dir();
  const auto start = std::chrono::steady_clock::now();
  try {
    tetrahedralize(box_mesh({1, 1, 1}), options, "box.obj");
    FAIL() << "TetGen's run was not stopped";
  } catch (const Interrupted& e) {
    EXPECT_EQ(std::string(e.what()), "interrupted during TetGen (SIGINT)");
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10);
}

}  // namespace
}  // namespace pd
