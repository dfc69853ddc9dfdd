#include "host/app/kernel_report.h"

#include <cstdio>

namespace pd {

std::vector<KernelRow> kernel_rows(const KernelStats& stats, const std::string& prefix, int64_t bonds,
                                   int64_t steps) {
  std::vector<KernelRow> rows;
  double total = 0;
  for (const auto& [name, s] : stats.table())
    if (name.rfind(prefix, 0) == 0) total += s.seconds;
  for (const auto& [name, s] : stats.table()) {
    if (name.rfind(prefix, 0) != 0 || s.launches == 0) continue;
    KernelRow r;
    r.name = name;
    r.seconds = s.seconds;
    r.launches = s.launches;
    r.ms_per_launch = 1e3 * s.seconds / double(s.launches);
    r.share = total > 0 ? s.seconds / total : 0;
    r.bond_updates_per_s = s.seconds > 0 ? double(bonds) * double(steps) / s.seconds : 0;
    r.registers = s.registers;
    r.occupancy = s.occupancy;
    rows.push_back(r);
  }
  KernelRow step;
  step.name = "step (all kernels)";
  step.seconds = total;
  step.launches = steps;
  step.ms_per_launch = steps > 0 ? 1e3 * total / double(steps) : 0;
  step.share = 1;
  step.bond_updates_per_s = total > 0 ? double(bonds) * double(steps) / total : 0;
  rows.push_back(step);
  return rows;
}

void print_kernel_table(std::ostream& os, const std::vector<KernelRow>& rows) {
  char line[256];
  std::snprintf(line, sizeof line, "%-22s %9s %10s %7s %14s %5s %6s\n", "kernel", "launches", "ms/launch",
                "share", "bond-upd/s", "regs", "occup");
  os << line;
  for (const auto& r : rows) {
    char regs[16] = "-", occ[16] = "-";
    if (r.registers >= 0) std::snprintf(regs, sizeof regs, "%d", r.registers);
    if (r.occupancy >= 0) std::snprintf(occ, sizeof occ, "%.2f", r.occupancy);
    std::snprintf(line, sizeof line, "%-22s %9lld %10.4f %6.1f%% %14.3e %5s %6s\n", r.name.c_str(),
                  (long long)r.launches, r.ms_per_launch, 100 * r.share, r.bond_updates_per_s, regs, occ);
    os << line;
  }
}

}  // namespace pd
