// Per-kernel timing statistics, filled by either backend's parallel_for (pbrt-v4 style).
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace pd {

// On the GPU each kernel's launches 0, 8, 16, ... are timed (two events each) and its time is
// estimated from those: recording the events of every launch took a third of a small scene's step
// on the host, which the GPU then waited for (bench/NOTES.md: 3,840 particles, 0.056 against
// 0.040 ms per step). The CPU backend times every launch.
constexpr int64_t kTimedLaunchStride = 8;

struct KernelStat {
  double seconds = 0;  // summed execution time (on the GPU: estimated from the timed launches)
  int64_t launches = 0;
  // The GPU times one launch in kTimedLaunchStride of each kernel (CudaExec): their sum and count.
  double timed_seconds = 0;
  int64_t timed_launches = 0;
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
      s.timed_seconds = 0;
      s.timed_launches = 0;
    }
  }
  // Each GPU kernel's time from its timed launches, scaled to all of them.
  void estimate_from_timed() {
    for (auto& [name, s] : table_)
      if (s.timed_launches > 0) s.seconds = s.timed_seconds * double(s.launches) / double(s.timed_launches);
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
