// A mesh collider's distance field: the distance to the mesh sampled once on a regular grid
// around it (negative inside a closed mesh; unsigned for an open sheet, which pushes from both
// sides), so the kernels find a particle's distance and normal by trilinear interpolation of 8
// values instead of a loop over triangles (cuda/kernels/colliders.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

struct DistanceGrid {
  Vec3d origin{0, 0, 0};  // node (0, 0, 0) [m]
  double cell = 0;        // node spacing [m]
  std::array<int32_t, 3> dims{0, 0, 0};
  std::vector<float> distance;  // per node, x fastest then y then z [m]
  bool solid = false;           // negative inside (a closed mesh)
};

// The nodes the grid of `mesh` would have with spacing `cell` and `margin` around its bounding
// box (for checking a limit before building it).
int64_t distance_grid_nodes(const TriMesh& mesh, double cell, double margin);

// Samples the distance to `mesh` on nodes of spacing `cell` covering its bounding box and `margin`
// around it; `closed`: signed by the inside test (InsideTest; the mesh must be a closed solid).
DistanceGrid distance_grid(const TriMesh& mesh, bool closed, double cell, double margin);

}  // namespace pd
