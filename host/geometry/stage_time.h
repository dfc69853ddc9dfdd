// Wall time of the stages of a particle build (surface mesh, TetGen, Poisson-disk sampling,
// cells, ...), kept with the result so `perifrac bench-geometry` can print the breakdown.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace pd {

struct StageTime {
  std::string name;
  double seconds = 0;
};

// Appends the time since the previous lap (or construction) under a name.
class StageClock {
 public:
  explicit StageClock(std::vector<StageTime>* out) : out_(out), last_(std::chrono::steady_clock::now()) {}
  void lap(const std::string& name) {
    const auto now = std::chrono::steady_clock::now();
    if (out_) out_->push_back({name, std::chrono::duration<double>(now - last_).count()});
    last_ = now;
  }

 private:
  std::vector<StageTime>* out_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace pd
