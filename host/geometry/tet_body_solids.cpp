#include "host/geometry/tet_body_solids.h"

#include <algorithm>

namespace pd {

TriMesh tet_boundary(const TetMesh& mesh) {
  // The face opposite corner k of a positively oriented tet, counter-clockwise seen from outside.
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  TriMesh surface;
  surface.vertices = mesh.vertices;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k)
      if (mesh.neighbors[t][size_t(k)] < 0) {
        const auto& c = mesh.tets[t];
        surface.triangles.push_back({c[size_t(kFace[k][0])], c[size_t(kFace[k][1])], c[size_t(kFace[k][2])]});
      }
  return surface;
}

void TetBodySolids::add(int32_t body, const TetMesh& mesh) {
  if (size_t(body) >= solids_.size()) solids_.resize(size_t(body) + 1);
  solids_[size_t(body)] = std::make_unique<const Solid>(tet_boundary(mesh));
}

bool TetBodySolids::has(int32_t body) const {
  return body >= 0 && size_t(body) < solids_.size() && solids_[size_t(body)];
}

void TetBodySolids::inside_along_x(int32_t body, double x0, double dx, double y, double z, int count,
                                   uint8_t* inside) const {
  thread_local std::vector<InsideTest::Crossing> xs;  // the crossings of the line (y, z), sorted
  solids_[size_t(body)]->test.crossings(y, z, xs);
  for (int k = 0; k < count; ++k) inside[k] = uint8_t(inside_of_row(xs, x0 + k * dx));
}

}  // namespace pd
