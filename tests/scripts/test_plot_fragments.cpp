// scripts/plot-fragments.sh: a run's fragments.csv drawn as pieces and mass shares over time.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class PlotFragmentsScript : public testing::TempDirTest {};

TEST_F(PlotFragmentsScript, PlotsARunsFragmentStatistics) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot on PATH";
  // A log with the free particles' column.
  const std::string with_free = path("with_free");
  std::filesystem::create_directories(with_free);
  std::ofstream(with_free + "/fragments.csv")
      << "frame,step,time,fragments,singles,single_mass_share,largest_mass_share,largest_particles,n_1,"
         "free_mass_share\n"
      << "0,0,0,1,0,0,1,400,0,0\n"
      << "1,100,0.001,12,5,0.0125,0.61,244,5,0.01\n";
  const std::string plot_free =
      std::string(PERIFRAC_SOURCE_DIR "/scripts/plot-fragments.sh ") + with_free + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(plot_free.c_str()), 0) << plot_free;
  EXPECT_GT(std::filesystem::file_size(with_free + "/fragments.png"), 10000u);
  // An older log without it.
  const std::string run = path("run");
  std::filesystem::create_directories(run);
  std::ofstream(run + "/fragments.csv")
      << "frame,step,time,fragments,singles,single_mass_share,largest_mass_share,largest_particles,n_1\n"
      << "0,0,0,1,0,0,1,400,0\n"
      << "1,100,0.001,12,5,0.0125,0.61,244,5\n"
      << "2,200,0.002,40,21,0.0525,0.44,176,21\n";
  const std::string command =
      std::string(PERIFRAC_SOURCE_DIR "/scripts/plot-fragments.sh ") + run + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_TRUE(std::filesystem::exists(run + "/fragments.png"));
  EXPECT_GT(std::filesystem::file_size(run + "/fragments.png"), 10000u);
  // A folder without the file: exit 2 with a message.
  EXPECT_NE(std::system((std::string(PERIFRAC_SOURCE_DIR "/scripts/plot-fragments.sh ") + path("none") +
                         " >/dev/null 2>&1")
                            .c_str()),
            0);
}

}  // namespace
}  // namespace pd
