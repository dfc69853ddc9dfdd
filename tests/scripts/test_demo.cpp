// The demo scene (scenes/demo_window.toml, run by scripts/demo.sh) breaks visibly: run as the
// demo's CPU preview runs it (scale, step and frames; tiny images), its last frame holds pieces of
// at least 8 particles beside the pane, the pane keeps less of the mass than it had, and the ball
// has gone through. About a minute on 2 cores.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/fragments/fragment_log.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class DemoScene : public testing::TempDirTest {};

// The fields of the last line of a CSV file.
std::vector<std::string> last_row(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::vector<std::string> fields;
  std::stringstream ss(last);
  for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
  return fields;
}

TEST_F(DemoScene, BreaksIntoPiecesThatFlyApart) {
  const std::string out = path("demo");
  const std::string command = std::string(PERIFRAC_BINARY) +
                              " run " PERIFRAC_SOURCE_DIR
                              "/scenes/demo_window.toml --backend cpu --scale 0.02 "
                              "--set simulation.dt=1.6e-6 --set simulation.steps_per_frame=625 --frames 24 "
                              "--set render.width=16 --set render.height=16 --set render.every=1000 --out " +
                              out + " > " + path("log") + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << testing::read_all(path("log"));
  // fragments.csv: frame, step, time, fragments, singles, single_mass_share, largest_mass_share,
  // largest_particles, then the pieces per size: 1, 2-3, 4-7, 8-15, ..., then free_mass_share.
  const std::vector<std::string> row = last_row(out + "/fragments.csv");
  ASSERT_EQ(row.size(), 9u + kFragmentLogBins);
  EXPECT_EQ(row[0], "24");
  int pieces_of_8 = 0;
  for (size_t k = 11; k < 8 + kFragmentLogBins; ++k) pieces_of_8 += std::stoi(row[k]);
  EXPECT_GE(pieces_of_8, 8) << "pieces of 8 particles or more, the pane included";
  EXPECT_LT(std::stod(row[6]), 0.97) << "the pane keeps less than 97% of the mass";
  // The ball's centre (colliders_00024.csv: frame, time, collider, shape, law, size x y z, centre
  // x y z, ...) is past the pane, which stands at z = 0.
  const std::vector<std::string> ball = last_row(out + "/colliders_00024.csv");
  ASSERT_GT(ball.size(), 10u);
  EXPECT_LT(std::stod(ball[10]), 0.0) << "the ball went through";
}

}  // namespace
}  // namespace pd
