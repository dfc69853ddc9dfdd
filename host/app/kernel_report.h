// The per-kernel table printed after a run and by `perifrac bench`.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "cuda/kernel_stats.h"

namespace pd {

struct KernelRow {
  std::string name;
  double seconds = 0, ms_per_launch = 0, share = 0;
  int64_t launches = 0;
  // Bonds of one step over this kernel's time per step; for an instantiation ("name[...]"), which
  // may run in some steps only, over its time per launch.
  double bond_updates_per_s = 0;
  int registers = -1;
  double occupancy = -1;
};

// Rows for the kernels whose name starts with `prefix` ("pd/" for the step kernels), one per
// instantiation ("pd/springforces[state,lattice]": its own time, registers and occupancy), a row
// "name (all)" after the instantiations of a kernel that has them, and a final "step" row summing
// every kernel. `bonds` is the number of stored bonds (both directions)
// and `steps` the number of steps the stats cover, of which `graphed` ran as CUDA graphs: their
// kernels are timed together as the row kStepGraphStat (cuda/engine/step_graphs.h), the other
// rows cover the steps outside graphs.
std::vector<KernelRow> kernel_rows(const KernelStats& stats, const std::string& prefix, int64_t bonds,
                                   int64_t steps, int64_t graphed = 0);

void print_kernel_table(std::ostream& os, const std::vector<KernelRow>& rows);

}  // namespace pd
