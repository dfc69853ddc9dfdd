// scripts/plot-speed.sh: the speed history plotted from benchmark results files.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class PlotSpeedScript : public testing::TempDirTest {};

// A results file as `perifrac bench` writes it, with one kernel and the step.
void write_result(const std::string& file, const char* workload, long particles, double kernel_rate,
                  double step_rate) {
  std::ofstream(file)
      << "{\"date\": \"2026-11-24T02:20:30Z\", \"git\": \"abc1234\", \"device\": \"NVIDIA H100 "
         "80GB HBM3\", \"backend\": \"cuda\", \"workload\": \""
      << workload << "\", \"particles\": " << particles
      << ", \"kernels\": [{\"name\": \"pd/springforces\", \"bond_updates_per_s\": " << kernel_rate
      << "}, {\"name\": \"step (all kernels)\", \"bond_updates_per_s\": " << step_rate << "}]}\n";
}

TEST_F(PlotSpeedScript, PlotsTheResultsOfLargeRuns) {
  if (std::system("command -v gnuplot >/dev/null 2>&1 && command -v python3 >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no gnuplot or python3 on PATH";
  const std::string results = path("results"), png = path("speed.png");
  std::filesystem::create_directories(results);
  write_result(results + "/20261124-022031_cuda_lattice100_h3_bond_based.json", "lattice100_h3_bond_based",
               1000000, 2.3e11, 2.1e11);
  write_result(results + "/20261124-022030_cuda_glass_plate_projectile.json", "glass_plate_projectile",
               1048576, 2.0e11, 1.26e11);
  write_result(results + "/20261124-022035_cuda_lattice100_h3_plastic.json", "lattice100_h3_plastic", 1000000,
               7.8e10, 4.0e10);
  write_result(results + "/20261124-022028_cuda_glass_plate_projectile.json", "glass_plate_projectile",
               131072, 1.5e11, 6.8e10);  // below 1M particles: left out
  std::ofstream(results + "/20261124-014459_cpu_render_slab_600000.json") << "{}\n";  // not a cuda result
  const std::string command =
      std::string(PERIFRAC_SOURCE_DIR "/scripts/plot-speed.sh ") + results + " " + png + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
}

}  // namespace
}  // namespace pd
