// The perifrac binary as a user runs it: clear one-line errors and exit codes for bad input,
// blow-up detection, and a small scene that runs to completion.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/output_scan.h"

namespace {

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

Result run_perifrac(const std::string& args, const std::string& env = "") {
  Result r;
  const std::string cmd = env + " " + std::string(PERIFRAC_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("perifrac_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  // A small valid scene with `extra` appended and `replace` substitutions applied.
  std::string scene(const std::string& body_lines, const std::string& extra = "") {
    const std::string path = (dir_ / "scene.toml").string();
    std::ofstream(path)
        << "[simulation]\nsteps_per_frame = 20\nframes = 2\n"
        << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
        << "[[bodies]]\nmaterial = \"glass\"\n"
        << body_lines << extra;
    return path;
  }
  std::string out() const { return (dir_ / "out").string(); }
  std::filesystem::path dir_;
};

const char* kGoodBody = "size = [0.02, 0.01, 0.01]\nspacing = 0.002\n";

TEST_F(Cli, SmallSceneRunsAndWritesFrames) {
  const Result r = run_perifrac("run " + scene(kGoodBody) + " --backend cpu --out " + out());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("bonds"), std::string::npos);
  EXPECT_NE(r.output.find("pd/springforces"), std::string::npos);
  for (const char* f : {"rest.pfr", "frame_00002.pfr", "frame_00002.vtu", "particles.pvd"})
    EXPECT_TRUE(std::filesystem::exists(out() + "/" + f)) << f;
}

// Each user mistake: exit code 2 and one line naming the file and the key.
void expect_scene_error(const Result& r, const std::string& key) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("scene.toml"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(key), std::string::npos) << r.output;
}

TEST_F(Cli, MissingKey) {
  expect_scene_error(
      run_perifrac("run " + scene("size = [0.02, 0.01, 0.01]\n") + " --backend cpu --out " + out()),
      "spacing");
}

TEST_F(Cli, UnknownKey) {
  expect_scene_error(
      run_perifrac("run " + scene(kGoodBody, "[world]\ngravty = [0, 0, 0]\n") + " --out " + out()), "gravty");
}

TEST_F(Cli, NegativeDensity) {
  const std::string path = scene(kGoodBody);
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  text.replace(text.find("density = 2200.0"), 16, "density = -5.0");
  std::ofstream(path) << text;
  expect_scene_error(run_perifrac("run " + path + " --out " + out()), "density");
}

TEST_F(Cli, HorizonBelowSpacing) {
  expect_scene_error(run_perifrac("run " +
                                  scene(kGoodBody,
                                        "[materials.soft]\ndensity = 1.0\nbulk_modulus = 1.0\n"
                                        "strain_limit = 0.1\nhorizon = 0.5\n") +
                                  " --out " + out()),
                     "horizon");
}

TEST_F(Cli, ZeroParticles) {
  expect_scene_error(
      run_perifrac("run " + scene("size = [0.02, 0.0001, 0.01]\nspacing = 0.002\n") + " --out " + out()),
      "size");
}

TEST_F(Cli, UnstableTimeStepIsRefused) {
  const std::string text = kGoodBody;
  const std::string path = (dir_ / "scene.toml").string();
  std::ofstream(path) << "[simulation]\ndt = 1e-4\nframes = 1\nsteps_per_frame = 5\n"
                      << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
                      << "[[bodies]]\nmaterial = \"glass\"\n"
                      << text;
  const Result u = run_perifrac("run " + path + " --out " + out());
  expect_scene_error(u, "simulation.dt");
  EXPECT_NE(u.output.find("--allow-unstable-dt"), std::string::npos);
}

// A collider too stiff for the scene's dt: refused, the message naming the colliders' push.
TEST_F(Cli, TooStiffColliderIsRefused) {
  const std::string path = (dir_ / "scene.toml").string();
  std::ofstream(path) << "[simulation]\ndt = 1e-7\nframes = 1\nsteps_per_frame = 5\n"
                      << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
                      << "[[bodies]]\nmaterial = \"glass\"\n"
                      << kGoodBody
                      << "[[colliders]]\nshape = \"plane\"\ncenter = [0, -0.1, 0]\nstiffness = 1e15\n";
  const Result u = run_perifrac("run " + path + " --out " + out());
  expect_scene_error(u, "simulation.dt");
  EXPECT_NE(u.output.find("colliders"), std::string::npos) << u.output;
}

// Collider mistakes through the binary: each one `error:` line naming the scene and the key, exit 2,
// before any work: an open mesh as a free body (it has no inside, so no mass), a negative mass,
// an unknown shape, a mesh file with no faces, a distance grid too fine to hold, a stiffness that
// leaves no stable time step.
TEST_F(Cli, ColliderMistakesAreOneLine) {
  std::ofstream(dir_ / "sheet.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir_ / "points.obj") << "v 0 0 0\nv 1 0 0\n";  // no faces
  const struct {
    std::string collider, key;
  } cases[] = {
      {"shape = \"mesh\"\nmesh = \"sheet.obj\"\ncenter = [0, 0.2, 0]\ndensity = 1000.0\n", "colliders[0]"},
      {"shape = \"sphere\"\nradius = 0.01\ncenter = [0, 0.2, 0]\nmass = -1.0\n", "colliders[0].mass"},
      {"shape = \"cone\"\ncenter = [0, 0.2, 0]\n", "colliders[0].shape"},
      {"shape = \"mesh\"\nmesh = \"points.obj\"\ncenter = [0, 0.2, 0]\n", "colliders[0].mesh"},
      {"shape = \"mesh\"\nmesh = \"sheet.obj\"\ncenter = [0, 0.2, 0]\ncell = 1e-9\n", "colliders[0].cell"},
      {"shape = \"sphere\"\nradius = 0.01\ncenter = [0, 0.2, 0]\nstiffness = 1e300\n", "colliders"},
  };
  for (const auto& c : cases) {
    const Result r = run_perifrac("run " + scene(kGoodBody, "[[colliders]]\n" + c.collider) +
                                  " --backend cpu --out " + out());
    expect_scene_error(r, c.key);
    size_t lines = 0;
    for (char ch : r.output) lines += ch == '\n';
    EXPECT_EQ(lines, 1u) << "one line, nothing before it\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out())) << c.collider;
  }
}

// dt = "auto" runs at half the stable time step and says so.
TEST_F(Cli, AutomaticTimeStep) {
  const std::string path = (dir_ / "scene.toml").string();
  std::ofstream(path) << "[simulation]\ndt = \"auto\"\nframes = 1\nsteps_per_frame = 5\n"
                      << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
                      << "[[bodies]]\nmaterial = \"glass\"\n"
                      << kGoodBody;
  const Result r = run_perifrac("run " + path + " --backend cpu --out " + out());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("= 0.50 dt_c (continuum estimate), chosen by dt = \"auto\""), std::string::npos)
      << r.output;
}

// A body so far from the origin that float positions lose its spacing: refused, naming the body.
TEST_F(Cli, BodyFarFromTheOriginIsRefused) {
  const Result r = run_perifrac("run " + scene(std::string(kGoodBody) + "center = [1e4, 0, 0]\n") +
                                " --backend cpu --out " + out());
  expect_scene_error(r, "bodies[0].center");
  EXPECT_EQ(run_perifrac("run " + scene(std::string(kGoodBody) + "center = [10, 0, 0]\n") +
                         " --backend cpu --out " + out())
                .exit_code,
            0);
}

TEST_F(Cli, MissingSceneFile) {
  const Result r = run_perifrac("run " + (dir_ / "nope.toml").string() + " --out " + out());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nope.toml"), std::string::npos) << r.output;
}

TEST_F(Cli, BadOptionValues) {
  // Command-line mistakes: one line starting "error:" that names the option, exit code 2.
  // Numbers out of range, NaN included, and values that would run without end or for nothing.
  for (const std::string& args :
       {"run " + scene(kGoodBody) + " --backend gpu", std::string("run"),
        "run " + scene(kGoodBody) + " --frames x", std::string("frobnicate"),
        "run " + scene(kGoodBody) + " --no-such-option",
        "run " + scene(kGoodBody) + " --checkpoint-minutes nan",
        "run " + scene(kGoodBody) + " --checkpoint-every -1",
        std::string("validate --problem wave_bar --delta-over-lambda 1e9"),
        std::string("validate --problem wave_bar --dt-fraction 50"),
        std::string("validate --problem wave_bar --dt-fraction 0"),
        std::string("validate --problem wave_bar --resolution 100000"), std::string("bench --horizon nan"),
        std::string("bench-geometry --tet-quality 0.5"), std::string("bench-geometry --spacing nan"),
        std::string("bench-render --kd-max-depth -3"), std::string("compare a b --position-tolerance -1"),
        std::string("render d --eye nan,0,0")}) {
    const Result bad = run_perifrac(args);
    EXPECT_EQ(bad.exit_code, 2) << args << "\n" << bad.output;
    EXPECT_EQ(bad.output.rfind("error: ", 0), 0u) << args << "\n" << bad.output;
    EXPECT_EQ(bad.output.find('\n'), bad.output.size() - 1) << "not one line: " << bad.output;
  }
  EXPECT_NE(run_perifrac("run " + scene(kGoodBody) + " --backend gpu").output.find("--backend"),
            std::string::npos);
  EXPECT_NE(run_perifrac("frobnicate").output.find("unknown command 'frobnicate' (allowed: run, "),
            std::string::npos);
  const Result r = run_perifrac("run " + scene(kGoodBody) + " --scale -1 --out " + out());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--scale"), std::string::npos) << r.output;
}

// `validate --particles voronoi` on a problem that runs on a grid only: one line naming the
// option, the problem and the problems that take scattered particles; exit code 2.
TEST_F(Cli, ValidateParticlesOnAGridOnlyProblem) {
  const Result r = run_perifrac("validate --problem cantilever_pmb --particles voronoi --resolution 4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "not one line: " << r.output;
  for (const char* word : {"--particles voronoi", "cantilever_pmb", "tension_bar_pmb, tension_bar_lps"})
    EXPECT_NE(r.output.find(word), std::string::npos) << word << "\n" << r.output;
  EXPECT_EQ(run_perifrac("validate --particles hexagons").exit_code, 2);
}

// Overflow to infinity (a huge dt, allowed explicitly) is caught at the end of the frame,
// with the step and the frames written so far kept.
TEST_F(Cli, BlowUpIsDetectedWithTheStep) {
  const std::string path = (dir_ / "scene.toml").string();
  // Particles of 1e-37 kg that start below the floor: its push overflows their acceleration.
  std::ofstream(path) << "[simulation]\ndt = 1e-7\nframes = 2\nsteps_per_frame = 20\n"
                      << "[world]\nfloor = true\nfloor_height = -0.003\n"
                      << "[materials.glass]\ndensity = 1e-29\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
                      << "[[bodies]]\nmaterial = \"glass\"\n"
                      << kGoodBody;
  const Result r = run_perifrac("run " + path + " --allow-unstable-dt --out " + out());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("numerical blow-up"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("step 20"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out() + "/frame_00000.pfr"));
  EXPECT_EQ(r.output.find("nan"), std::string::npos) << r.output;
  EXPECT_EQ(pd::testing::non_finite_outputs(out()), std::vector<std::string>{});
}

// Finite but extreme numbers are refused before anything is written, naming the key to change
// (not the time step they make unstable), in finite numbers.
TEST_F(Cli, ExtremeNumbersAreRefusedBeforeAnyOutput) {
  const std::string path = scene(kGoodBody);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"materials.glass.density=1e308", "materials.glass.density"},
      {"materials.glass.density=1e-308", "materials.glass.density"},
      {"bodies[0].velocity=[0,0,1e300]", "bodies[0].velocity"},
      {"bodies[0].velocity=[1e30,0,0]", "bodies[0].velocity"},
      {"materials.glass.bulk_modulus=1e300", "materials.glass"}};
  for (const auto& [set, key] : cases) {
    std::filesystem::remove_all(out());
    const Result r = run_perifrac("run " + path + " --set '" + set + "' --backend cpu --out " + out());
    EXPECT_EQ(r.exit_code, 2) << set << "\n" << r.output;
    EXPECT_NE(r.output.find("error: " + path + ": " + key + ":"), std::string::npos) << set << "\n"
                                                                                     << r.output;
    EXPECT_FALSE(pd::testing::has_non_finite_token(r.output)) << set << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out())) << set << ": the refused run made its folder";
  }
}

// A run past the stable time step (--allow-unstable-dt) stops once its energy grows 10%, with
// finite numbers in the message and in every file written.
TEST_F(Cli, UnstableRunsStopOnAGrowingEnergy) {
  const std::string drop = std::string(PERIFRAC_SOURCE_DIR) + "/scenes/validation/stress_drop.toml";
  const Result stable = run_perifrac("run " + drop + " --frames 0 --backend cpu --out " + out());
  ASSERT_EQ(stable.exit_code, 0) << stable.output;
  const size_t at = stable.output.find("dt_c ");
  ASSERT_NE(at, std::string::npos) << stable.output;
  const double critical = std::stod(stable.output.substr(at + 5));
  const Result r = run_perifrac("run " + drop + " --set simulation.dt=" + std::to_string(2 * critical) +
                                " --allow-unstable-dt --backend cpu --overwrite --out " + out());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("past the stable time step a run stops at 0.1"), std::string::npos) << r.output;
  EXPECT_FALSE(pd::testing::has_non_finite_token(r.output)) << r.output;
  EXPECT_EQ(pd::testing::non_finite_outputs(out()), std::vector<std::string>{});
}

// --frames: 0 runs the set-up and writes frame 0, as frames = 0 in a scene does; past the bound
// (10^9) it is refused in one line, not clamped.
TEST_F(Cli, FrameCountsAreBounded) {
  const Result zero = run_perifrac("run " + scene(kGoodBody) + " --frames 0 --backend cpu --out " + out());
  EXPECT_EQ(zero.exit_code, 0) << zero.output;
  EXPECT_TRUE(std::filesystem::exists(out() + "/frame_00000.pfr"));
  EXPECT_FALSE(std::filesystem::exists(out() + "/frame_00001.pfr"));
  const std::string path = (dir_ / "zero.toml").string();
  std::ofstream(path) << "[simulation]\nframes = 0\n"
                      << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
                      << "[[bodies]]\nmaterial = \"glass\"\n"
                      << kGoodBody;
  const Result scene_zero = run_perifrac("run " + path + " --backend cpu --out " + (dir_ / "z").string());
  EXPECT_EQ(scene_zero.exit_code, 0) << scene_zero.output;
  for (const char* frames : {"99999999999999999999", "1000000001", "-1"}) {
    const Result big = run_perifrac("run " + scene(kGoodBody) + " --frames " + frames + " --out " + out());
    EXPECT_EQ(big.exit_code, 2) << big.output;
    EXPECT_EQ(big.output.rfind("error: --frames", 0), 0u) << big.output;
    EXPECT_EQ(big.output.find('\n'), big.output.size() - 1) << "not one line: " << big.output;
  }
}

// Too many particles for the machine's memory: refused before set-up makes them, exit code 2.
TEST_F(Cli, SceneLargerThanMemoryIsRefused) {
  const Result r = run_perifrac(
      "run " + scene("size = [0.1, 0.1, 0.1]\nspacing = 0.001\n") + " --backend cpu --out " + out(),
      "PERIFRAC_HOST_MEMORY_MB=20");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("1000000 particles"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("free host memory"), std::string::npos) << r.output;
}

}  // namespace
