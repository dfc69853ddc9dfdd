// Tetrahedralization by the TetGen program (Debian package `tetgen`, AGPL), run as an external
// process on files: it is never linked, so its licence does not extend to perifrac.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "host/geometry/stage_time.h"
#include "host/geometry/tet_mesh.h"
#include "host/geometry/tri_mesh.h"

namespace pd {

// The "(allowed: ...)" text that ends a TetGen failure's message (also how callers tell one).
extern const std::string kTetgenAllowed;

// TetGen's -q bound as scenes (tet_quality) and bench-geometry take it: 0 (no quality refinement)
// or a radius-edge bound in [1.1, 10] (below, TetGen may refine without end).
constexpr const char* kTetQualityAllowed = "0 (no quality refinement) or a radius-edge bound in [1.1, 10]";
inline bool tet_quality_allowed(double q) {
  return q == 0 || (q >= 1.1 && q <= 10);
}

struct TetgenOptions {
  double quality = 1.414;     // -q: bound on the radius-edge ratio of the tets; 0 = no quality refinement
  double max_volume = 0;      // -a: bound on each tet's volume [m^3]; 0 = none
  bool keep_surface = false;  // -Y: no Steiner points on the surface (its triangles are tet faces)
  std::vector<Vec3d> extra_points;  // -i: points to insert (inside the solid)
  std::string work_dir;  // where the .smesh and output files go; empty = a temporary folder, removed after
  std::vector<StageTime>* stages = nullptr;  // when set, gets the time of writing, TetGen and reading
  // Called once TetGen has started (or its tets come from the cache), for work that may overlap
  // it: a check that throws stops TetGen, and its exception goes on.
  std::function<void()> while_running;
};

// The path of the tetgen program on PATH, or empty.
std::string find_tetgen();

// Tetrahedralizes the closed, outward mesh `surface` (checked by check_solid) with
// `tetgen -p[Y][q][a][i]O0zFQ` (O0: see tetgen.cpp). Throws MeshError (naming `name`) when tetgen is missing
// — with the install command — or fails, quoting its last message.
TetMesh tetrahedralize(const TriMesh& surface, const TetgenOptions& options, const std::string& name);

}  // namespace pd
