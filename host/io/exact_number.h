// A double as a C99 hex float ("%a", e.g. 0x1.47ae147ae147bp-6), which reads back exactly with
// strtod: the numbers of checkpoints and run manifests.
#pragma once

#include <cstdio>
#include <string>

namespace pd {

inline std::string exact_number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%a", v);
  return text;
}

}  // namespace pd
