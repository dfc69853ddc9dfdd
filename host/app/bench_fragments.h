// `perifrac bench-fragments`: times the per-frame fragment outputs (components, rigid fits, the
// split crack mesh and its files, the rest-space piece meshes) on one body of grid cubes, tets or
// Voronoi cells, intact, cut into blocks and shattered into single particles, plus the one-off
// set-up (families, adjacency, element complex), and appends CSV rows when asked.
// A benchmark, not a test: scripts/bench-fragments.sh runs the table of docs/fragments.md.
#pragma once

#include <cstdint>
#include <string>

namespace pd {

struct FragmentsBenchOptions {
  std::string particles = "grid";  // grid (a cube of cubes) | tets (cubes of 6 tets) | voronoi (a sphere)
  int64_t count = 600000;          // wanted particles (the printed count is the real one)
  double horizon = 0;              // delta / lambda; 0: 3 for grid and voronoi, 1.5 for tets
  int blocks = 6;                  // the cut state: blocks^3 fragments
  int frames = 3;   // timed frames per state (the first one after the change is reported apart)
  int threads = 0;  // OpenMP threads; 0 = OpenMP's default
  std::string out;  // folder for the files written; empty: a temporary folder, removed after
  std::string csv;  // when set, rows are appended (a header first when the file is new)
};

int bench_fragments_command(const FragmentsBenchOptions& options);

}  // namespace pd
