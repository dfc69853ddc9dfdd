// A tetrahedral mesh: TetGen's vertices and tets (.node, .ele) and the face neighbours found from
// them (face_neighbors), kept for the stages that split it along cracks (Chen sec. 5.2). Its
// surface is the faces without a neighbour (tet_body_solids.h, tet_boundary).
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

  double volume(size_t t) const;
  Vec3d barycenter(size_t t) const;
};

// For each tet, the tet across the face opposite each corner k (the other tet holding that
// face's three vertices), -1 where none does: TetGen's .neigh, found from the tets alone through
// the tets around each vertex, in parallel. Corners must lie in [0, vertex_count).
std::vector<std::array<int32_t, 4>> face_neighbors(const std::vector<std::array<int32_t, 4>>& tets,
                                                   size_t vertex_count);

}  // namespace pd
