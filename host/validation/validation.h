// Validation problems with analytic or published answers (docs/validation.md): each builds a
// SimulationInput, runs it on an engine and compares one or more measured figures with their
// reference values.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"

namespace pd {

// The default dt / dt_c with the ghost correction, whose bonds shorten the stable step below the
// continuum dt_c the problems scale: each run measures its step on the engine and refuses a dt past
// it (validation_engine, lattice.h). Measured on one H200 (2026-11-29, every elastic problem at its
// default resolutions and the notched bar at 20): the step with ghosts is 0.65-0.79 dt_c, so 0.3
// is 0.38-0.46 of it, and the figures are those at 0.125 to the digits printed (docs/validation.md).
constexpr double kGhostDtFraction = 0.3;

// One run's settings. `resolution` counts particles across the problem's characteristic
// length (the bar or beam width, the plate height, the crack-tip disc's radius).
struct ValidationCase {
  int resolution = 0;
  double delta_over_lambda = 3;
  double dt_fraction = 0.5;  // dt / dt_c, dt_c from the continuum estimate (host/material.h)
  // The surface correction (cuda/kernels/surface_correction.h); none: each model's default (on
  // for bond-based materials, off for state-based ones).
  std::optional<bool> surface_correction;
  bool surface_ghosts = false;  // the ghost correction instead (cuda/kernels/surface_ghosts.h)
  Backend backend = Backend::kCpu;
  // The particles: "grid" (simple cubic), or, in the problems that take them
  // (ValidationProblem::scattered), the same solid filled with "voronoi" cells or TetGen "tets"
  // of about the grid's spacing, lambda then their median nearest-neighbour distance.
  std::string particles = "grid";
  // crack_branching: the step traction on the plate's edges [Pa]; 0: its default, 3.04 MPa
  // (docs/validation.md).
  double traction = 0;
};

// One measured figure of one run.
struct ValidationResult {
  std::string problem;  // "problem/figure", e.g. "tension_bar_pmb/poisson"
  double measured = 0, reference = 0;
  double rel_error = 0;  // |measured - reference| / |reference|
  int64_t particles = 0, steps = 0;
  double wall_s = 0;  // engine set-up and stepping, measurement included
  std::string note;   // a few words on what else the run showed
};

ValidationResult make_result(std::string problem, double measured, double reference);

using ValidationRun = std::vector<ValidationResult> (*)(const ValidationCase&);

struct ValidationProblem {
  const char* name;
  const char* summary;
  std::vector<int> resolutions;  // the benchmark's default sweep, coarse to fine
  ValidationRun run;
  bool scattered = false;  // also runs on Voronoi cells and tets (ValidationCase::particles)
};

// The registered problems, in the order `validate all` runs them.
const std::vector<ValidationProblem>& validation_problems();

// The problems, one file each.
std::vector<ValidationResult> run_wave_bar(const ValidationCase& c);
std::vector<ValidationResult> run_tension_bar_pmb(const ValidationCase& c);
std::vector<ValidationResult> run_tension_bar_lps(const ValidationCase& c);
std::vector<ValidationResult> run_cantilever_pmb(const ValidationCase& c);
std::vector<ValidationResult> run_cantilever_lps(const ValidationCase& c);
std::vector<ValidationResult> run_bar_twist_lps(const ValidationCase& c);
std::vector<ValidationResult> run_bar_spin_lps(const ValidationCase& c);
std::vector<ValidationResult> run_crack_branching(const ValidationCase& c);
std::vector<ValidationResult> run_notched_bar_pmb(const ValidationCase& c);
std::vector<ValidationResult> run_crack_tip_pmb(const ValidationCase& c);

}  // namespace pd
