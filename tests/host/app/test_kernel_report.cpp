// The kernel table: one row per kernel instantiation, with its own registers and occupancy, a
// summed row per kernel that has instantiations, and the step row.
#include "host/app/kernel_report.h"

#include <gtest/gtest.h>

#include <sstream>

#include "cuda/engine/step_graphs.h"

namespace pd {
namespace {

TEST(KernelReport, InstantiationsGetTheirOwnRowsAndASum) {
  KernelStats stats;
  auto set = [&](const std::string& name, double seconds, int64_t launches, int registers) {
    KernelStat& s = stats.entry(name);
    s.seconds = seconds;
    s.launches = launches;
    s.registers = registers;
  };
  set("pd/init", 1.0, 10, 20);
  set("pd/springforces[lattice]", 2.0, 4, 48);
  set("pd/springforces[lattice,screened]", 3.0, 6, 40);
  set("pd/velocity_update", 4.0, 10, 16);
  set("family/count", 9.0, 1, 30);  // not a step kernel
  const auto rows = kernel_rows(stats, "pd/", 1000, 10);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].name, "pd/init");
  // In name order (',' sorts before ']').
  EXPECT_EQ(rows[1].name, "pd/springforces[lattice,screened]");
  EXPECT_EQ(rows[1].registers, 40);
  EXPECT_EQ(rows[2].name, "pd/springforces[lattice]");
  EXPECT_EQ(rows[2].registers, 48);
  EXPECT_DOUBLE_EQ(rows[2].bond_updates_per_s, 1000.0 * 4 / 2.0);  // per launch: it ran in 4 steps
  EXPECT_EQ(rows[3].name, "pd/springforces (all)");
  EXPECT_DOUBLE_EQ(rows[3].seconds, 5.0);
  EXPECT_EQ(rows[3].launches, 10);
  EXPECT_EQ(rows[3].registers, -1);
  EXPECT_DOUBLE_EQ(rows[3].bond_updates_per_s, 1000.0 * 10 / 5.0);
  EXPECT_EQ(rows[4].name, "pd/velocity_update");
  EXPECT_EQ(rows[5].name, "step (all kernels)");
  EXPECT_DOUBLE_EQ(rows[5].seconds, 10.0);  // the sum row is not counted twice
  EXPECT_DOUBLE_EQ(rows[3].share, 0.5);
  std::ostringstream table;
  print_kernel_table(table, rows);
  EXPECT_NE(table.str().find("pd/springforces[lattice,screened]"), std::string::npos);
}

// Steps run as CUDA graphs are timed as one row: its rate is over the graphed steps, the other
// kernels' over the steps outside the graphs, and the step row over all.
TEST(KernelReport, GraphedStepsHaveTheirOwnRow) {
  KernelStats stats;
  stats.entry(kStepGraphStat).seconds = 6.0;
  stats.entry(kStepGraphStat).launches = 3;
  stats.entry("pd/init").seconds = 1.0;
  stats.entry("pd/init").launches = 4;
  const auto rows = kernel_rows(stats, "pd/", 1000, 100, 96);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].name, "pd/init");
  EXPECT_DOUBLE_EQ(rows[0].bond_updates_per_s, 1000.0 * 4 / 1.0);
  EXPECT_EQ(rows[1].name, kStepGraphStat);
  EXPECT_DOUBLE_EQ(rows[1].bond_updates_per_s, 1000.0 * 96 / 6.0);
  EXPECT_DOUBLE_EQ(rows[2].bond_updates_per_s, 1000.0 * 100 / 7.0);
}

}  // namespace
}  // namespace pd
