// The CPU backend's launch primitives (cuda/exec_cpu.h) beyond parallel_for; the GPU's
// parallel_phases is checked through the contact lists' relisting, whose rounds it runs
// (gpu-check: relisting against full builds, bit for bit).
#include "cuda/exec_cpu.h"

#include <gtest/gtest.h>

#include <vector>

namespace pd {
namespace {

// Each phase reads what the one before wrote for other items, and each runs over its own count.
TEST(CpuExec, PhasesRunInOrderAndCountAsOneLaunch) {
  KernelStats stats;
  CpuExec ex(&stats);
  constexpr int64_t kN = 1000;
  std::vector<int64_t> a(kN, -1), b(kN, -1), c(2 * kN, -1);
  int64_t* pa = a.data();
  int64_t* pb = b.data();
  int64_t* pc = c.data();
  ex.parallel_phases(
      "test/phases", {kN, kN, 2 * kN}, [=](int64_t i) { pa[i] = i; },
      [=](int64_t i) { pb[i] = pa[kN - 1 - i] + 1; },
      [=](int64_t i) { pc[i] = pb[i / 2] + pa[(i + 7) % kN]; });
  for (int64_t i = 0; i < kN; ++i) EXPECT_EQ(b[size_t(i)], kN - i) << i;
  for (int64_t i = 0; i < 2 * kN; ++i) EXPECT_EQ(c[size_t(i)], kN - i / 2 + (i + 7) % kN) << i;
  EXPECT_EQ(stats.entry("test/phases").launches, 1);
}

}  // namespace
}  // namespace pd
