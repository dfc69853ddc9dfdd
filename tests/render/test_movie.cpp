// movie.mp4 from rendered frames (render/movie.h): made atomically when ffmpeg is on PATH (the
// test skips without it), a clear note when it is not, nothing left behind when ffmpeg fails.
#include "render/movie.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "host/io/png_file.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

class Movie : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("perifrac_movie_[glob]_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Files in the folder whose name holds ".tmp." (left-over temporaries).
  int temporaries() const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir_))
      n += e.path().filename().string().find(".tmp.") != std::string::npos;
    return n;
  }
  fs::path dir_;
};

TEST_F(Movie, EncodesTheFramesWithFfmpeg) {
  if (find_on_path("ffmpeg").empty()) GTEST_SKIP() << "ffmpeg is not on PATH";
  // Three frames of an odd size (padded to even for yuv420p), numbered with a gap as `every` does.
  for (int f : {0, 2, 4}) {
    ImageRGB8 image;
    image.width = 33;
    image.height = 21;
    image.rgb.assign(3 * 33 * 21, uint8_t(40 * f));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", f);
    write_png((dir_ / name).string(), image);
  }
  const MovieResult r = make_movie(dir_.string());
  ASSERT_TRUE(r.made) << r.message;
  EXPECT_EQ(r.message, (dir_ / kMovieFileName).string());
  std::ifstream in(dir_ / kMovieFileName, std::ios::binary);
  char head[8] = {};
  in.read(head, 8);
  EXPECT_EQ(std::string(head + 4, 4), "ftyp");  // an ISO media (MP4) file
  EXPECT_EQ(temporaries(), 0);
}

TEST_F(Movie, FailedEncodingLeavesNothingBehind) {
  if (find_on_path("ffmpeg").empty()) GTEST_SKIP() << "ffmpeg is not on PATH";
  const MovieResult r = make_movie(dir_.string());  // no frames to encode
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.message.find("ffmpeg failed"), std::string::npos) << r.message;
  EXPECT_FALSE(fs::exists(dir_ / kMovieFileName));
  EXPECT_EQ(temporaries(), 0);
}

TEST_F(Movie, WithoutFfmpegSaysSo) {
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", dir_.c_str(), 1);  // a folder without ffmpeg
  const MovieResult r = make_movie(dir_.string());
  setenv("PATH", saved.c_str(), 1);
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.message.find("ffmpeg is not on PATH"), std::string::npos) << r.message;
  EXPECT_TRUE(find_on_path("perifrac-no-such-program").empty());
}

}  // namespace
}  // namespace pd
