// TetGen as an external program: a run that does not end is stopped, with a message that says
// what TetGen needs, instead of hanging the scene's set-up.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "host/geometry/shapes.h"
#include "host/geometry/tetgen.h"
#include "tests/support/scoped_env.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

TEST(Tetgen, ARunPastItsTimeIsStoppedWithAMessage) {
  // A `tetgen` that never finishes, first on PATH.
  const fs::path dir = fs::temp_directory_path() / ("perifrac-test-tetgen-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    std::ofstream script(dir / "tetgen");
    script << "#!/bin/sh\nexec sleep 60\n";
  }
  fs::permissions(dir / "tetgen", fs::perms::owner_all);
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (dir.string() + ":" + old_path).c_str(), 1);
  testing::ScopedEnv limit("PERIFRAC_TETGEN_SECONDS", "1");
  TetgenOptions options;
  options.work_dir = (dir / "work").string();  // no cache
  const auto start = std::chrono::steady_clock::now();
  std::string message;
  try {
    tetrahedralize(box_mesh({1, 1, 1}), options, "box.obj");
  } catch (const MeshError& e) {
    message = e.what();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  setenv("PATH", old_path.c_str(), 1);
  fs::remove_all(dir);
  EXPECT_NE(message.find("box.obj"), std::string::npos) << message;
  EXPECT_NE(message.find("was stopped after 1 s"), std::string::npos) << message;
  EXPECT_NE(message.find("shell_thickness"), std::string::npos) << message;
  EXPECT_LT(seconds, 10);
}

}  // namespace
}  // namespace pd
