// `perifrac bench` (host/app/bench.h): what it says of the run besides its rates, here whether
// the workload broke bonds, printed and in the JSON, for a scene that fractures and for the elastic
// lattice that must not.
#include "host/app/bench.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "cuda/engine/memory_budget.h"
#include "host/scene/scene.h"
#include "tests/support/scene_texts.h"
#include "tests/support/scoped_env.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

using testing::read_all;

class Bench : public testing::TempDirTest {
 protected:
  // Runs the bench; returns what it printed, and the JSON it wrote in `json`.
  std::string run(BenchOptions opt, std::string& json) {
    opt.backend = "cpu";
    opt.out = path("results");
    ::testing::internal::CaptureStdout();
    const int code = bench_command(opt);
    const std::string printed = ::testing::internal::GetCapturedStdout();
    EXPECT_EQ(code, 0) << printed;
    for (const auto& e : std::filesystem::directory_iterator(opt.out)) json = read_all(e.path().string());
    return printed;
  }
};

// The count printed on the "broken" line and the JSON's, which must agree.
int64_t broken_bonds(const std::string& printed, const std::string& json) {
  std::smatch line, field;
  if (!std::regex_search(printed, line, std::regex(R"(broken +(\d+) of \d+ bonds after (\d+) steps)")) ||
      !std::regex_search(json, field, std::regex(R"("broken_bonds": (\d+))"))) {
    ADD_FAILURE() << "no broken-bond count in\n" << printed << "\n" << json;
    return -1;
  }
  EXPECT_EQ(line[1].str(), field[1].str());
  return std::stoll(line[1].str());
}

TEST_F(Bench, ReportsTheBondsAnImpactBroke) {
  const std::string scene = path("impact.toml");
  std::ofstream(scene) << testing::kPlateImpactScene;
  BenchOptions opt;
  opt.scene = scene;
  opt.warmup = 20;
  opt.steps = 100;
  std::string json;
  EXPECT_EQ(broken_bonds(run(opt, json), json), 0);  // the plate holds at its strain limit (1%)
  // A brittle plate (--set) breaks: about a thousand bonds in these 120 steps.
  std::filesystem::remove_all(path("results"));
  opt.overrides = {"materials.metal.strain_limit=0.001"};
  const std::string printed = run(opt, json);
  EXPECT_GT(broken_bonds(printed, json), 100);
  EXPECT_NE(printed.find("after 120 steps"), std::string::npos) << printed;  // warm-up included
}

// A dt past the stable step is refused naming the key, as `perifrac run` refuses it, unless
// allowed; the allowed run says it is unstable.
TEST_F(Bench, RefusesAnUnstableTimeStepUnlessAllowed) {
  const std::string scene = path("impact.toml");
  std::ofstream(scene) << testing::kPlateImpactScene;
  BenchOptions opt;
  opt.scene = scene;
  opt.backend = "cpu";
  opt.out = path("results");
  opt.overrides = {"simulation.dt=2e-6"};
  opt.warmup = 0;
  opt.steps = 2;
  try {
    bench_command(opt);
    ADD_FAILURE() << "an unstable dt was timed";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(scene), std::string::npos) << message;
    EXPECT_NE(message.find("simulation.dt"), std::string::npos) << message;
    EXPECT_NE(message.find("allowed: dt <="), std::string::npos) << message;
  }
  opt.allow_unstable_dt = true;
  std::string json;
  const std::string printed = run(opt, json);
  EXPECT_NE(printed.find("(unstable, allowed by --allow-unstable-dt)"), std::string::npos) << printed;
}

// A scene with ghosts is timed at the step `perifrac run` takes: dt = "auto" is half the stable
// step measured on the engine, which the JSON's dt_over_stable is taken against.
TEST_F(Bench, TimesAGhostSceneAtHalfTheMeasuredStep) {
  BenchOptions opt;
  opt.scene = PERIFRAC_SOURCE_DIR "/scenes/chen_bar_twist.toml";
  opt.scale = 0.1;
  opt.overrides = {"materials.rubber.surface_correction=\"ghosts\""};
  opt.warmup = 2;
  opt.steps = 5;
  std::string json;
  const std::string printed = run(opt, json);
  EXPECT_NE(printed.find("= 0.50 of the measured (ghosts) stable step"), std::string::npos) << printed;
  std::smatch field;
  ASSERT_TRUE(std::regex_search(json, field, std::regex(R"("dt_over_stable": ([0-9.e+-]+))"))) << json;
  EXPECT_NEAR(std::stod(field[1].str()), 0.5, 1e-6);
}

TEST_F(Bench, ReportsNoBrokenBondForTheElasticLattice) {
  BenchOptions opt;
  opt.lattice = 10;
  opt.warmup = 2;
  opt.steps = 10;
  std::string json;
  const std::string printed = run(opt, json);
  EXPECT_EQ(broken_bonds(printed, json), 0);
}

// A lattice past the memory the backend has is refused before anything is allocated.
TEST_F(Bench, ALatticeThatDoesNotFitIsRefusedUpFront) {
  const testing::ScopedEnv small("PERIFRAC_HOST_MEMORY_MB", "100");
  BenchOptions opt;
  opt.backend = "cpu";
  opt.lattice = 400;  // 64M particles: far past 100 MiB
  try {
    bench_command(opt);
    FAIL() << "the lattice was set up";
  } catch (const ResourceError& e) {
    EXPECT_NE(std::string(e.what()).find("--lattice 400 is 64000000 particles"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pd
