// Per-kernel timing statistics, filled by either backend's parallel_for (pbrt-v4 style).
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace pd {

struct KernelStat {
  double seconds = 0;  // summed execution time
  int64_t launches = 0;
  int registers = -1;     // per thread (GPU only)
  double occupancy = -1;  // theoretical, active warps / max warps per SM (GPU only)
  int block_size = 0;
};

class KernelStats {
 public:
  KernelStat& entry(const std::string& name) { return table_[name]; }
  const std::map<std::string, KernelStat>& table() const { return table_; }
  void reset_times() {
    for (auto& [name, s] : table_) {
      s.seconds = 0;
      s.launches = 0;
    }
  }
  double total_seconds() const {
    double t = 0;
    for (const auto& [name, s] : table_) t += s.seconds;
    return t;
  }

 private:
  std::map<std::string, KernelStat> table_;
};

}  // namespace pd
