// `perifrac profile`: step ranges are parsed strictly, and a small scene gives a row per step
// kernel and range in the CSV, with the timeline covering the run.
#include "host/app/profile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

TEST(ProfileRanges, ParsesSortsAndRefusesBadRanges) {
  const auto r = parse_step_ranges("500:600,0:100");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0], std::make_pair(int64_t(0), int64_t(100)));
  EXPECT_EQ(r[1], std::make_pair(int64_t(500), int64_t(600)));
  for (const char* bad : {"", "5", "10:5", "-1:3", "0:10,5:20", "0:10x", "a:b", "0:99999999999999999999",
                          "0:1099511627777", ":5", "0:"})
    EXPECT_THROW(parse_step_ranges(bad), std::invalid_argument) << bad;
}

class Profile : public testing::TempDirTest {};

TEST_F(Profile, SmallSceneWritesRangesAndTimeline) {
  std::ofstream(path("scene.toml")) << "[simulation]\nsteps_per_frame = 10\nframes = 4\n"
                                    << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\n"
                                    << "strain_limit = 5e-4\n[[bodies]]\nmaterial = \"glass\"\n"
                                    << "size = [0.02, 0.01, 0.01]\nspacing = 0.002\n";
  ProfileOptions o;
  o.scene = path("scene.toml");
  o.backend = "cpu";
  o.ranges = "0:10,20:40";
  o.timeline = 5;
  o.out = path("results");
  ASSERT_EQ(profile_command(o), 0);
  std::string profile, timeline;
  for (const auto& e : std::filesystem::directory_iterator(o.out)) {
    const std::string name = e.path().filename().string();
    if (name.find("_profile.csv") != std::string::npos) profile = testing::read_all(e.path().string());
    if (name.find("_timeline.csv") != std::string::npos) timeline = testing::read_all(e.path().string());
  }
  // Steps run 5 at a time (the timeline's step): each 5 end with one velocity update, and the
  // other 4 steps' velocity updates run with the next step's position update.
  for (const char* row : {"\n0,10,springforces,10,", "\n20,40,springforces,20,", "\n20,40,velocity_update,4,",
                          "\n20,40,velocity_position_update,16,"})
    EXPECT_NE(profile.find(row), std::string::npos) << row << " in\n" << profile;
  EXPECT_NE(timeline.find("\n35,40,springforces,"), std::string::npos) << timeline;
  EXPECT_EQ(timeline.find("\n40,"), std::string::npos) << "the timeline runs past the last range";
  // A timeline of more points than it may hold is refused before the engine runs.
  o.ranges.clear();
  o.steps = 100000000;
  o.timeline = 1;
  try {
    profile_command(o);
    FAIL() << "a timeline of 1e8 points was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--timeline 1000 or more"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pd
