// `perifrac run` with a [render] block (render/live_render.h) and the render command's options,
// through the binary as a user runs them: frames rendered as the run goes, every N-th, with a
// movie when ffmpeg is present; tet bodies written as tets.ptt and drawn as tetrahedra; an
// unusable .hdr is a one-line user error (exit 2) naming the file and the key.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/fragments/tet_file.h"
#include "host/geometry/tetgen.h"
#include "render/movie.h"

#include "tests/support/stb_png.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

Result run_perifrac(const std::string& args) {
  Result r;
  FILE* p = popen((std::string(PERIFRAC_BINARY) + " " + args + " 2>&1").c_str(), "r");
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

class LiveRender : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("perifrac_live_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A small scene of 2 frames with `body` and `render` appended.
  std::string scene(const std::string& body, const std::string& render) {
    const std::string path = (dir_ / "scene.toml").string();
    std::ofstream(path)
        << "[simulation]\nsteps_per_frame = 10\nframes = 2\n"
        << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
        << "[[bodies]]\nmaterial = \"glass\"\n"
        << body << render;
    return path;
  }
  std::string out() const { return (dir_ / "out").string(); }
  fs::path dir_;
};

const char* kGridBody = "size = [0.02, 0.01, 0.01]\nspacing = 0.002\n";

// A PNG's pixels (RGB, row by row); empty when it does not load.
using testing_png::Png;
using testing_png::read_png;

// A body's look from [render.bodies.NAME] colours it in the run's images, and `perifrac render`
// of the finished run takes the scene's [render] block (camera, size, looks) unless an option
// says otherwise; damage colours only on request.
TEST_F(LiveRender, BodyLooksColourTheLiveAndTheLaterImages) {
  const std::string look =
      "[render]\nwidth = 32\nheight = 24\nspp = 1\nlook_at = [0, 0, 0]\n"
      "eye = [0, 0, 0.08]\n[render.bodies.slab]\nlook = \"clay\"\n"
      "color = [0.9, 0.02, 0.02]\n";
  const Result r = run_perifrac("run " + scene("name = \"slab\"\n" + std::string(kGridBody), look) +
                                " --backend cpu --out " + out());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("looks per body"), std::string::npos) << r.output;
  const Png live = read_png(out() + "/render/frame_00002.png");
  ASSERT_EQ(live.width, 32);
  const unsigned char* centre = live.at(16, 12);
  EXPECT_GT(int(centre[0]), 3 * int(centre[1]) + 10) << "the slab is drawn in its red";
  EXPECT_GT(int(centre[0]), 3 * int(centre[2]) + 10);

  // Later: the same settings from the scene give the same image.
  const Result again =
      run_perifrac("render " + out() + " --backend cpu --frames 2 --out " + out() + "/again");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("settings   the scene's [render] block"), std::string::npos) << again.output;
  EXPECT_EQ(read_png(out() + "/again/frame_00002.png").rgb, live.rgb);
  // An option given wins over the scene; --material replaces the looks.
  const Result wide = run_perifrac(
      "render " + out() + " --backend cpu --frames 2 --width 40 --material opaque --out " + out() + "/wide");
  ASSERT_EQ(wide.exit_code, 0) << wide.output;
  const Png w = read_png(out() + "/wide/frame_00002.png");
  ASSERT_EQ(w.width, 40);
  const unsigned char* grey = w.at(20, 12);
  EXPECT_LT(int(grey[0]), 2 * int(grey[1])) << "the default palette is no red";
}

// every = 0: nothing is rendered while the run goes, and the block still gives `perifrac render`
// its settings (the gallery's scenes carry their looks this way).
TEST_F(LiveRender, EveryZeroRendersNothingButKeepsTheLooks) {
  const std::string look =
      "[render]\nevery = 0\nwidth = 32\nheight = 24\nspp = 1\nlook_at = [0, 0, 0]\n"
      "eye = [0, 0, 0.08]\n[render.bodies.slab]\ncolor = [0.9, 0.02, 0.02]\n";
  const Result r = run_perifrac("run " + scene("name = \"slab\"\n" + std::string(kGridBody), look) +
                                " --backend cpu --out " + out());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out() + "/render")) << r.output;
  const Result later = run_perifrac("render " + out() + " --backend cpu --frames 2");
  ASSERT_EQ(later.exit_code, 0) << later.output;
  const Png image = read_png(out() + "/render/frame_00002.png");
  ASSERT_EQ(image.width, 32);
  const unsigned char* centre = image.at(16, 12);
  EXPECT_GT(int(centre[0]), 3 * int(centre[1]) + 10) << "the slab in its colour";
}

TEST_F(LiveRender, BodyLookMistakesNameTheKey) {
  const struct {
    const char* render;
    const char* message;
  } cases[] = {
      {"[render.bodies.slab]\nlook = \"marble\"\n", "render.bodies.slab.look"},
      {"[render.bodies.lid]\nlook = \"clay\"\n", "render.bodies.lid"},
      {"[render.bodies.slab]\ncolor = [1.5, 0, 0]\n", "render.bodies.slab.color"},
      {"[render.bodies.slab]\n", "names neither a look nor a colour"},
      {"[render]\ndamage_colors = 1\n", "render.damage_colors"},
  };
  for (const auto& c : cases) {
    const std::string render =
        std::string(c.render).rfind("[render]", 0) == 0 ? c.render : "[render]\n" + std::string(c.render);
    const Result r = run_perifrac("run " + scene("name = \"slab\"\n" + std::string(kGridBody), render) +
                                  " --backend cpu --out " + out());
    EXPECT_EQ(r.exit_code, 2) << c.render << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.render << r.output;
  }
}

TEST_F(LiveRender, RunRendersEveryNthFrameAsItGoes) {
  const Result r = run_perifrac("run " +
                                scene(kGridBody,
                                      "[render]\nwidth = 32\nheight = 24\nspp = 1\nevery = 2\n"
                                      "eye = [0.05, 0.04, 0.06]\nmaterial = \"glass\"\n") +
                                " --backend cpu --out " + out());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out() + "/render/frame_00000.png"));
  EXPECT_FALSE(fs::exists(out() + "/render/frame_00001.png"));
  EXPECT_TRUE(fs::exists(out() + "/render/frame_00002.png"));
  EXPECT_NE(r.output.find("render     2 frames"), std::string::npos) << r.output;
  if (find_on_path("ffmpeg").empty())
    EXPECT_NE(r.output.find("ffmpeg is not on PATH"), std::string::npos) << r.output;
  else
    EXPECT_TRUE(fs::exists(out() + "/render/movie.mp4")) << r.output;
}

TEST_F(LiveRender, UnreadableEnvironmentIsAUserError) {
  const Result r = run_perifrac("run " + scene(kGridBody, "[render]\nenvironment = \"nowhere.hdr\"\n") +
                                " --backend cpu --out " + out());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("scene.toml: render.environment: cannot read environment"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("nowhere.hdr"), std::string::npos) << r.output;
}

TEST_F(LiveRender, TetBodiesAreWrittenAndDrawnAsTetrahedra) {
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  const Result run = run_perifrac(
      "run " + scene("shape = \"sphere\"\nradius = 0.01\nspacing = 0.004\nparticles = \"tets\"\n", "") +
      " --backend cpu --frames 1 --out " + out());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const EmbeddedTets tets = read_tets_file(out() + "/" + kTetsFileName);
  ASSERT_GT(tets.tets.size(), 20u);
  const Result r =
      run_perifrac("render " + out() + " --backend cpu --width 32 --height 24 --spp 1 --no-movie " +
                   "--eye 0.05,0.03,0.04 --look-at 0,0,0 --vfov 30 --material glass --ior 1.33");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("0 cubes, " + std::to_string(tets.tets.size()) + " tetrahedra"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(out() + "/render/frame_00001.png"));
  EXPECT_FALSE(fs::exists(out() + "/render/movie.mp4"));
  // An unreadable .hdr on the command line: exit 2, one line naming the file.
  const Result bad =
      run_perifrac("render " + out() + " --backend cpu --environment " + (dir_ / "x.hdr").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("error: cannot read environment '" + (dir_ / "x.hdr").string() + "'"),
            std::string::npos)
      << bad.output;
}

// A run resumed after an interrupt that left an image unwritten draws it with its first frame,
// and its movie has every image.
TEST_F(LiveRender, AResumeDrawsTheImagesAnInterruptLeftUnwritten) {
  const std::string render = "[render]\nwidth = 32\nheight = 24\nspp = 1\n";
  ASSERT_EQ(
      run_perifrac("run " + scene(kGridBody, render) + " --backend cpu --checkpoint-every 1 --out " + out())
          .exit_code,
      0);
  fs::remove(out() + "/render/frame_00001.png");  // (as an interrupt in its image leaves it)
  const Result r = run_perifrac("run --resume " + out() + " --frames 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int f = 0; f <= 3; ++f)
    EXPECT_TRUE(fs::exists(out() + "/render/frame_0000" + std::to_string(f) + ".png")) << f << "\n"
                                                                                       << r.output;
}

}  // namespace
}  // namespace pd
