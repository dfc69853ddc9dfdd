// `perifrac bench-geometry`: times the making of one body's particles (grid cubes, TetGen tets,
// fattened-shell tets or Voronoi cells) from a procedural shape or a mesh file, with the time of
// each stage, the particle count and the volume error, and appends a CSV row when asked.
// A benchmark, not a test: scripts/bench-geometry.sh runs the table of docs/geometry.md.
#pragma once

#include <cstdint>
#include <string>

namespace pd {

struct GeometryBenchOptions {
  std::string shape = "sphere";       // sphere (radius 0.1 m) | vase (radius 0.1, height 0.3) | mesh
  std::string mesh;                   // shape = mesh: an OBJ, PLY or STL file, used at its own scale
  std::string particles = "voronoi";  // grid | tets | shell | voronoi
  int64_t count = 600000;             // wanted particles: sets the spacing (see bench_geometry.cpp)
  double spacing = 0;                 // the spacing itself [m]; overrides count
  double tet_quality = 1.414;         // TetGen -q bound (tets, shell)
  bool tet_keep_surface = false;      // TetGen -Y (tets, shell)
  double shell_thickness = 0.008;     // shell: depth of the vase's wall [m]
  int threads = 0;                    // threads of the parallel stages; 0 = OpenMP's default
  uint64_t seed = 1;
  std::string csv;  // when set, a row is appended (a header first when the file is new)
};

int bench_geometry_command(const GeometryBenchOptions& options);

}  // namespace pd
