// scripts/profile_table.py: scripts/profile.sh's per-kernel table from an Nsight Compute --csv report.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/external_tools.h"
#include "tests/support/ncu_report.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class ProfileTableScript : public testing::TempDirTest {};

// A kernel run over a particle range is wrapped by launch_over_range: the table names it by its
// variant (springforces), not by the wrapper.
TEST_F(ProfileTableScript, NamesEachKernelByItsVariantAndGivesItsBytesPerBond) {
  if (testing::find_program("python3").empty()) GTEST_SKIP() << "no python3 on PATH";
  const std::string csv = path("report.csv");
  {
    testing::NcuReport report(csv);
    report.metric(0, testing::kNcuPositionUpdate, "gpu__time_duration.sum", "24,000");
    for (int launch : {1, 2}) {
      report.metric(launch, testing::kNcuSpringforces, "gpu__time_duration.sum", "400,000");
      report.metric(launch, testing::kNcuSpringforces, "dram__bytes_read.sum", "96,000");
      report.metric(launch, testing::kNcuSpringforces, "dram__bytes_write.sum", "32,000");
      report.metric(launch, testing::kNcuSpringforces, "launch__registers_per_thread", "32");
    }
  }
  const std::string table =
      testing::run_command("python3 " PERIFRAC_SOURCE_DIR "/scripts/profile_table.py " + csv + " 64000");
  // Two launches of 400 us moving 128,000 bytes each: 0.32 GB/s, 2 bytes a bond.
  EXPECT_NE(table.find("| springforces | 2 | 400.0 | 0 | 0 | 0 | 0 | 0 | 2.00 | 32 | 0 |"), std::string::npos)
      << table;
  EXPECT_NE(table.find("| position_update | 1 | 24.0 |"), std::string::npos) << table;
  EXPECT_EQ(table.find("over_range"), std::string::npos) << table;
}

}  // namespace
}  // namespace pd
