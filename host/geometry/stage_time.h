// Wall time of the stages of a particle build (surface mesh, TetGen, Poisson-disk sampling,
// cells, ...), kept with the result so `perifrac bench-geometry` can print the breakdown.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "host/io/interrupt.h"

namespace pd {

struct StageTime {
  std::string name;
  double seconds = 0;
};

// Appends the time since the previous lap (or construction) under a name. A lap is a point where
// the stage's results are complete: an interrupted command stops there (throw_if_interrupted),
// unless the clock was made without stop points.
class StageClock {
 public:
  explicit StageClock(std::vector<StageTime>* out, bool stop_points = true)
      : out_(out), stop_points_(stop_points), last_(std::chrono::steady_clock::now()) {}
  void lap(const std::string& name) {
    const auto now = std::chrono::steady_clock::now();
    if (out_) out_->push_back({name, std::chrono::duration<double>(now - last_).count()});
    last_ = now;
    if (stop_points_) throw_if_interrupted("set-up");
  }

 private:
  std::vector<StageTime>* out_;
  bool stop_points_;
  std::chrono::steady_clock::time_point last_;
};

// Replaces the last stage of `stages` by what `parts` leave of it, named `rest` (left out when
// nothing is left), and then `parts`, each named with `prefix` before its own name.
inline void split_last_stage(std::vector<StageTime>& stages, const std::vector<StageTime>& parts,
                             const std::string& prefix, const std::string& rest) {
  if (stages.empty() || parts.empty()) return;
  StageTime whole = stages.back();
  stages.pop_back();
  for (const StageTime& part : parts) whole.seconds -= part.seconds;
  if (whole.seconds > 0) stages.push_back({rest, whole.seconds});
  for (const StageTime& part : parts) stages.push_back({prefix + part.name, part.seconds});
}

}  // namespace pd
