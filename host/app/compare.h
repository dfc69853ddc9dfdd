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

// 0 when every common frame agrees, 1 when one does not.
int compare_command(const CompareOptions& options);

}  // namespace pd
