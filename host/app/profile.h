// `perifrac profile SCENE --ranges 0:1000,50000:51000`: per-kernel time per step in chosen step
// ranges (before, during and after fracture, as Levine et al.'s Table 2), the broken-bond
// fraction at the end of each range, theoretical occupancy, and a timeline of the time per
// kernel over the run. On CUDA every range is an NVTX range "pd-range-A-B", so Nsight Compute
// can add achieved occupancy for exactly those steps (scripts/profile-occupancy.sh).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pd {

struct ProfileOptions {
  std::string scene;
  double scale = 1.0;
  std::string backend = "auto";
  std::string ranges;    // "A:B,C:D" in steps; empty: the run cut into 5 equal ranges
  int64_t steps = -1;    // steps to run; default: the end of the last range, or the scene's length
  int64_t timeline = 0;  // timeline resolution in steps; 0: about 100 points over the run
  std::string out = "bench/results";
};

// Parses "A:B,C:D" into sorted, disjoint [A, B) ranges with 0 <= A < B. Throws
// std::invalid_argument naming the bad entry.
std::vector<std::pair<int64_t, int64_t>> parse_step_ranges(const std::string& text);

int profile_command(const ProfileOptions& options);

}  // namespace pd
