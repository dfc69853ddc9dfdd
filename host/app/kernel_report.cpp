#include "host/app/kernel_report.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "cuda/engine/step_graphs.h"

namespace pd {

std::vector<KernelRow> kernel_rows(const KernelStats& stats, const std::string& prefix, int64_t bonds,
                                   int64_t steps, int64_t graphed) {
  std::vector<KernelRow> rows;
  double total = 0;
  for (const auto& [name, s] : stats.table())
    if (name.rfind(prefix, 0) == 0) total += s.seconds;
  // Instantiations of one kernel ("name[features]") sum into a row "name (all)" after them.
  std::map<std::string, KernelRow> all;
  for (const auto& [name, s] : stats.table()) {
    if (name.rfind(prefix, 0) != 0 || s.launches == 0) continue;
    const size_t bracket = name.find('[');
    if (bracket != std::string::npos) {
      KernelRow& a = all[name.substr(0, bracket) + " (all)"];
      a.seconds += s.seconds;
      a.launches += s.launches;
    }
  }
  // An instantiation runs in some steps only (the screened and breaking passes alternate): its
  // rate is per launch, the bonds of one step over its time per launch; the graphs' is per
  // graphed step, other rows' per step outside the graphs.
  auto add_row = [&](KernelRow r) {
    r.ms_per_launch = r.launches > 0 ? 1e3 * r.seconds / double(r.launches) : 0;
    r.share = total > 0 ? r.seconds / total : 0;
    const bool instantiation = r.name.find('[') != std::string::npos;
    const double runs = instantiation              ? double(r.launches)
                        : r.name == kStepGraphStat ? double(graphed)
                                                   : double(steps - graphed);
    r.bond_updates_per_s = r.seconds > 0 ? double(bonds) * runs / r.seconds : 0;
    rows.push_back(r);
  };
  for (const auto& [name, s] : stats.table()) {
    if (name.rfind(prefix, 0) != 0 || s.launches == 0) continue;
    KernelRow r;
    r.name = name;
    r.seconds = s.seconds;
    r.launches = s.launches;
    r.registers = s.registers;
    r.occupancy = s.occupancy;
    add_row(r);
    // The sum row follows the last instantiation of its kernel.
    const size_t bracket = name.find('[');
    if (bracket == std::string::npos) continue;
    const std::string base = name.substr(0, bracket);
    const auto next = stats.table().upper_bound(name);
    if (next != stats.table().end() && next->first.rfind(base + "[", 0) == 0) continue;
    KernelRow a = all[base + " (all)"];
    a.name = base + " (all)";
    add_row(a);
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
  size_t width = 22;
  for (const auto& r : rows) width = std::max(width, r.name.size());
  std::snprintf(line, sizeof line, "%-*s %9s %10s %7s %14s %5s %6s\n", int(width), "kernel", "launches",
                "ms/launch", "share", "bond-upd/s", "regs", "occup");
  os << line;
  for (const auto& r : rows) {
    char regs[16] = "-", occ[16] = "-";
    if (r.registers >= 0) std::snprintf(regs, sizeof regs, "%d", r.registers);
    if (r.occupancy >= 0) std::snprintf(occ, sizeof occ, "%.2f", r.occupancy);
    std::snprintf(line, sizeof line, "%-*s %9lld %10.4f %6.1f%% %14.3e %5s %6s\n", int(width), r.name.c_str(),
                  (long long)r.launches, r.ms_per_launch, 100 * r.share, r.bond_updates_per_s, regs, occ);
    os << line;
  }
}

}  // namespace pd
