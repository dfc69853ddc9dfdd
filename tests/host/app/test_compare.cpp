// `perifrac compare A B`: two runs agree only when they hold the same complete frames, at the same
// steps and times, with displacements and damage within the tolerances.
#include "host/app/compare.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "host/app/run_folder.h"
#include "host/io/frame_file.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

class Compare : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(::testing::TempDir()) /
        ("perifrac_compare_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
         "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A run of 8 particles in `name` with frames 0..frames, particle 0 moving by `speed` per frame
  // (steps_per_frame steps a frame), and the manifest a finished run leaves.
  std::string run(const std::string& name, int frames, double speed = 0.001, int steps_per_frame = 10) {
    const fs::path dir = dir_ / name;
    fs::create_directories(dir);
    RestData rest;
    for (int i = 0; i < 8; ++i) {
      rest.position.push_back({real(0.01 * i), 0, 0});
      rest.volume.push_back(1e-6f);
      rest.body.push_back(0);
      rest.material.push_back(0);
    }
    write_rest_file((dir / kRestFileName).string(), rest);
    for (int f = 0; f <= frames; ++f) {
      FrameData frame;
      frame.frame = f;
      frame.step = int64_t(f) * steps_per_frame;
      frame.time = 1e-6 * double(frame.step);
      frame.position = rest.position;
      frame.position[0].y += real(speed * f);
      frame.velocity.assign(8, {0, 0, 0});
      frame.damage.assign(8, 0.0f);
      frame.body = rest.body;
      write_frame_file((dir / frame_file_name(f, "pfr")).string(), frame);
    }
    std::ofstream(dir / kManifestFileName) << "perifrac test\nscene_path /s.toml\nscene_hash 1\nscale 1\n"
                                              "overrides 0\nframes_written "
                                           << frames << "\n";
    return dir.string();
  }

  int compare(const std::string& a, const std::string& b) {
    CompareOptions o;
    o.a = a;
    o.b = b;
    return compare_command(o);
  }

  fs::path dir_;
};

TEST_F(Compare, TheSameRunAgrees) {
  EXPECT_EQ(compare(run("a", 3), run("b", 3)), 0);
}

TEST_F(Compare, AFrameInOneFolderOnlyDiffers) {
  const std::string a = run("a", 3), b = run("b", 2);
  EXPECT_EQ(compare(a, b), 1);
  EXPECT_EQ(compare(b, a), 1);
  // A frame past the manifest's (the one a killed run was writing) is not compared.
  std::ofstream(fs::path(b) / kManifestFileName, std::ios::trunc)
      << "perifrac test\nscene_path /s.toml\nscene_hash 1\nscale 1\noverrides 0\nframes_written 1\n";
  EXPECT_EQ(compare(run("c", 1), b), 0);
}

TEST_F(Compare, OtherStepsOrMotionDiffer) {
  EXPECT_EQ(compare(run("a", 2), run("b", 2, 0.001, 20)), 1);   // the same positions at other steps
  EXPECT_EQ(compare(run("c", 2, 0.0), run("d", 2, 0.001)), 1);  // only B moved: infinitely far
  EXPECT_EQ(compare(run("e", 2, 0.0), run("f", 2, 0.0)), 0);    // both at rest
}

TEST_F(Compare, FoldersThatHoldNoRunAreRefused) {
  const std::string a = run("a", 1);
  fs::create_directories(dir_ / "empty");
  EXPECT_THROW(compare(a, (dir_ / "empty").string()), std::invalid_argument);
  EXPECT_THROW(compare(a, (dir_ / "missing").string()), std::invalid_argument);
  EXPECT_THROW(compare(a, (fs::path(a) / kRestFileName).string()), std::invalid_argument);
}

}  // namespace
}  // namespace pd
