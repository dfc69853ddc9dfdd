// `perifrac validate`: runs validation problems (validation.h) at a list of resolutions, prints
// one line per measured figure and appends the rows to a CSV file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "host/validation/validation.h"

namespace pd {

struct ValidateOptions {
  std::string problem = "all";      // a name from validation_problems(), or "all"
  std::vector<int> resolutions;     // empty: each problem's default sweep
  double delta_over_lambda = 3;     // horizon in spacings, >= 1
  double dt_fraction = 0;           // dt / dt_c, > 0; 0: 0.5, or kGhostDtFraction with ghosts
  std::string backend = "cpu";      // "cpu" | "cuda" | "auto"
  std::string surface = "default";  // surface correction: "default" (each model's) | "on" | "off" | "ghosts"
  std::string particles = "grid";   // "grid" | "voronoi" | "tets" (ValidationCase::particles)
  std::optional<double> traction_mpa;  // crack_branching's edge traction [MPa]; none: its 3.04
  std::string csv;                     // rows appended here (header first when the file is new); "" = none
  bool quiet = false;                  // no per-row lines on stdout
};

// The CSV header (bench/accuracy/accuracy.csv).
extern const char* const kValidationCsvHeader;

// Returns 0 when every run finished with finite results, 2 for a bad option (message on
// stderr), 3 when a run produced a non-finite figure.
int validate_command(const ValidateOptions& options);

}  // namespace pd
