// Tetrahedralization by the TetGen program (Debian package `tetgen`, AGPL), run as an external
// process on files: it is never linked, so its licence does not extend to perifrac.
#pragma once

#include <string>
#include <vector>

#include "tet_mesh.h"
#include "tri_mesh.h"

namespace pd {

struct TetgenOptions {
  double quality = 1.414;  // -q: bound on the radius-edge ratio of the tets; 0 = no quality refinement
  double max_volume = 0;   // -a: bound on each tet's volume [m^3]; 0 = none
  std::vector<Vec3d> extra_points;  // -i: points to insert (inside the solid)
  std::string work_dir;  // where the .smesh and output files go; empty = a temporary folder, removed after
};

// The path of the tetgen program on PATH, or empty.
std::string find_tetgen();

// Tetrahedralizes the closed, outward mesh `surface` (checked by check_solid) with
// `tetgen -p[q][a][i]nzQ`. Throws MeshError (naming `name`) when tetgen is missing — with the
// install command — or fails, quoting its last message.
TetMesh tetrahedralize(const TriMesh& surface, const TetgenOptions& options, const std::string& name);

}  // namespace pd
