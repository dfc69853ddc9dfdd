// movie.mp4 from rendered frames (render/movie.h): made atomically from the images given, when
// ffmpeg is on PATH (the test skips without it), a clear note when it is not, nothing left behind
// when ffmpeg fails.
#include "render/movie.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

// The frame count of a movie as ffprobe reads it; -1 without ffprobe.
int movie_frames(const fs::path& movie) {
  const std::string ffprobe = find_on_path("ffprobe");
  if (ffprobe.empty()) return -1;
  const std::string command = ffprobe +
                              " -v error -count_frames -select_streams v:0 -show_entries "
                              "stream=nb_read_frames -of csv=p=0 '" +
                              movie.string() + "'";
  FILE* p = popen(command.c_str(), "r");
  if (!p) return -1;
  char line[64] = {};
  const bool read = std::fgets(line, sizeof line, p) != nullptr;
  pclose(p);
  return read ? std::atoi(line) : -1;
}

TEST_F(Movie, EncodesTheGivenImagesWithFfmpeg) {
  if (find_on_path("ffmpeg").empty()) GTEST_SKIP() << "ffmpeg is not on PATH";
  // Three frames of an odd size (padded to even for yuv420p), numbered with a gap as `every` does,
  // and an image of another render beside them, which the movie must not take.
  std::vector<std::string> images;
  for (int f : {0, 2, 4, 6}) {
    ImageRGB8 image;
    image.width = f == 6 ? 16 : 33;
    image.height = f == 6 ? 16 : 21;
    image.rgb.assign(size_t(3 * image.width * image.height), uint8_t(40 * f));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", f);
    write_png((dir_ / name).string(), image);
    if (f != 6) images.push_back((dir_ / name).string());
  }
  const MovieResult r = make_movie(images, (dir_ / kMovieFileName).string());
  ASSERT_TRUE(r.made) << r.message;
  EXPECT_EQ(r.message, (dir_ / kMovieFileName).string());
  std::ifstream in(dir_ / kMovieFileName, std::ios::binary);
  char head[8] = {};
  in.read(head, 8);
  EXPECT_EQ(std::string(head + 4, 4), "ftyp");  // an ISO media (MP4) file
  EXPECT_EQ(temporaries(), 0);
  const int frames = movie_frames(dir_ / kMovieFileName);
  if (frames >= 0) {
    EXPECT_EQ(frames, 3);
  }
}

TEST_F(Movie, FailedEncodingLeavesNothingBehind) {
  if (find_on_path("ffmpeg").empty()) GTEST_SKIP() << "ffmpeg is not on PATH";
  std::ofstream((dir_ / "frame_00000.png").string()) << "not a PNG image";
  const MovieResult r = make_movie({(dir_ / "frame_00000.png").string()}, (dir_ / kMovieFileName).string());
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.message.find("ffmpeg failed"), std::string::npos) << r.message;
  EXPECT_FALSE(fs::exists(dir_ / kMovieFileName));
  EXPECT_EQ(temporaries(), 0);
}

TEST_F(Movie, NoImagesNoMovie) {
  const MovieResult r = make_movie({}, (dir_ / kMovieFileName).string());
  EXPECT_FALSE(r.made);
  EXPECT_FALSE(fs::exists(dir_ / kMovieFileName));
}

TEST_F(Movie, WithoutFfmpegSaysSo) {
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", dir_.c_str(), 1);  // a folder without ffmpeg
  const MovieResult r = make_movie({(dir_ / "frame_00000.png").string()}, (dir_ / kMovieFileName).string());
  setenv("PATH", saved.c_str(), 1);
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.message.find("ffmpeg is not on PATH"), std::string::npos) << r.message;
  EXPECT_TRUE(find_on_path("perifrac-no-such-program").empty());
}

}  // namespace
}  // namespace pd
