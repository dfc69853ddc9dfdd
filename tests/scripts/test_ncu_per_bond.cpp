// scripts/ncu_per_bond.py: the bond loops' table from an Nsight Compute --csv report.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class NcuPerBondScript : public testing::TempDirTest {};

// One metric row of `ncu --csv --print-units base`, for kernel launch `id`.
void write_metric(std::ofstream& out, int id, const std::string& kernel, const std::string& metric,
                  const std::string& value) {
  out << '"' << id << "\",\"1136\",\"perifrac\",\"127.0.0.1\",\"1136 \",\"\",\"" << kernel
      << "\",\"1\",\"7\",\"(256, 1, 1)\",\"(3907, 1, 1)\",\"0\",\"9.0\",\"Command line profiler metrics\",\""
      << metric << "\",\"\",\"" << value << "\"\n";
}

std::string run(const std::string& command) {
  std::string text;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return text;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), int(buffer.size()), pipe)) text += buffer.data();
  if (pclose(pipe) != 0) text += "\n(exit status not 0)";
  return text;
}

TEST_F(NcuPerBondScript, TabulatesTheBondLoopsPerBondAndLeavesTheOthersOut) {
  if (std::system("command -v python3 >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3 on PATH";
  const std::string csv = path("report.csv");
  {
    std::ofstream out(csv);
    // The bench's own lines come first in the report; then ncu's header and its metric rows.
    out << "==PROF== Connected to process 1136\nsize       1000 particles, 64000 bonds\n";
    out << "\"ID\",\"Process ID\",\"Process Name\",\"Host Name\",\"thread Domain\",\"Id:Domain\",";
    out << "\"Kernel Name\",\"Context\",\"Stream\",\"Block Size\",\"Grid Size\",\"Device\",\"CC\",";
    out << "\"Section Name\",\"Metric Name\",\"Metric Unit\",\"Metric Value\"\n";
    const std::string update =
        "void parallel_for_kernel<void launch_position_update_variant<0, 1, CudaExec>(T3 &)>(long, T1)";
    const std::string forces =
        "void parallel_for_bounded_kernel<8, void launch_over_range<1, 8, CudaExec, void "
        "launch_springforces_variant<0, 0, 0, 0, 0, 1, 0, 1, CudaExec>(T9 &)>(long, T2)";
    write_metric(out, 0, update, "gpu__time_duration.sum", "24,096");
    write_metric(out, 0, update, "smsp__inst_executed.sum", "2,000,000");
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
    for (const auto& [metric, value] : metrics) write_metric(out, 1, forces, metric, value);
  }
  const std::string table = run("python3 " PERIFRAC_SOURCE_DIR "/scripts/ncu_per_bond.py " + csv + " 64000");
  ASSERT_EQ(table.find("exit status"), std::string::npos) << table;
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
