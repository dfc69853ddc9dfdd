// scripts/ncu_per_bond.py: the bond loops' table from an Nsight Compute --csv report.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "tests/support/external_tools.h"
#include "tests/support/ncu_report.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class NcuPerBondScript : public testing::TempDirTest {};

TEST_F(NcuPerBondScript, TabulatesTheBondLoopsPerBondAndLeavesTheOthersOut) {
  if (testing::find_program("python3").empty()) GTEST_SKIP() << "no python3 on PATH";
  const std::string csv = path("report.csv");
  {
    testing::NcuReport report(csv);
    report.metric(0, testing::kNcuPositionUpdate, "gpu__time_duration.sum", "24,096");
    report.metric(0, testing::kNcuPositionUpdate, "smsp__inst_executed.sum", "2,000,000");
    const std::pair<const char*, const char*> metrics[] = {
        {"gpu__time_duration.sum", "425,184"},
        {"smsp__inst_executed.sum", "130,000"},
        {"smsp__issue_active.avg.pct_of_peak_sustained_active", "73.41"},
        {"smsp__thread_inst_executed_per_inst_executed.ratio", "31.59"},
        {"smsp__average_warp_latency_per_inst_issued.ratio", "18.49"},
        {"smsp__average_warps_issue_stalled_not_selected_per_issue_active.ratio", "6.6"},
        {"smsp__average_warps_issue_stalled_long_scoreboard_per_issue_active.ratio", "4.9"},
        {"smsp__average_warps_issue_stalled_wait_per_issue_active.ratio", "2.0"},
        {"smsp__average_warps_issue_stalled_selected_per_issue_active.ratio", "7.0"},
        {"smsp__average_warps_issue_stalled_barrier_per_issue_active.ratio", "0.1"},
        {"sm__warps_active.avg.pct_of_peak_sustained_active", "87.4"},
        {"launch__registers_per_thread", "32"},
        {"gpu__dram_throughput.avg.pct_of_peak_sustained_elapsed", "27.03"},
        {"l1tex__t_sector_hit_rate.pct", "75.76"},
        {"lts__t_sector_hit_rate.pct", "45.35"},
    };
    for (const auto& [name, value] : metrics) report.metric(1, testing::kNcuSpringforces, name, value);
  }
  const std::string table =
      testing::run_command("python3 " PERIFRAC_SOURCE_DIR "/scripts/ncu_per_bond.py " + csv + " 64000");
  // 130,000 warp instructions over 64,000 bonds: 65.0 thread instructions a bond. The stalls
  // largest first, "selected" (issuing, not a stall) left out; the position update has no row.
  EXPECT_NE(
      table.find("| springforces<0, 0, 0, 0, 0, 1, 0, 1> | 0.425 | 0.1M | 65.0 | 73.4% | 31.6 | 18.49 | "
                 "not selected 6.6, long scoreboard 4.9, wait 2.0 | 87.4% | 32 | 27.0% | 75.8% | 45.4% |"),
      std::string::npos)
      << table;
  EXPECT_EQ(table.find("position_update"), std::string::npos) << table;
}

}  // namespace
}  // namespace pd
