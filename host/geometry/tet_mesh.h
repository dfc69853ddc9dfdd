// A tetrahedral mesh as TetGen writes it (.node, .ele, .neigh, .face), kept for the stages
// that split it along cracks (Chen sec. 5.2).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "host/geometry/vec3d.h"

namespace pd {

struct TetMesh {
  std::vector<Vec3d> vertices;
  std::vector<std::array<int32_t, 4>> tets;       // positively oriented (volume > 0)
  std::vector<std::array<int32_t, 4>> neighbors;  // tet across the face opposite corner k, -1 on the boundary
  std::vector<std::array<int32_t, 3>> boundary_faces;  // surface triangles of the tet mesh

  double volume(size_t t) const;
  Vec3d barycenter(size_t t) const;
};

}  // namespace pd
