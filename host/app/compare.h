// `perifrac compare A B`: compares two output folders frame by frame (e.g. a CPU-reference
// run against a GPU run of the same scene) and says whether they agree within tolerances.
#pragma once

#include <string>

namespace pd {

struct CompareOptions {
  std::string a, b;
  double position_tolerance = 1e-3;  // relative L2 of the displacement
  double damage_tolerance = 0.02;    // mean absolute damage difference
};

// 0 when both folders hold the same complete frames (run_folder.h) and each pair agrees: the same
// step and time (to 1e-6 relative), the displacement and the damage within the tolerances; 1 otherwise.
// Throws std::invalid_argument for a folder that is not a run's.
int compare_command(const CompareOptions& options);

}  // namespace pd
