#include "host/geometry/tet_mesh.h"

namespace pd {

double TetMesh::volume(size_t t) const {
  const auto& k = tets[t];
  const Vec3d& a = vertices[size_t(k[0])];
  return dot(vertices[size_t(k[1])] - a, cross(vertices[size_t(k[2])] - a, vertices[size_t(k[3])] - a)) / 6;
}

Vec3d TetMesh::barycenter(size_t t) const {
  const auto& k = tets[t];
  return 0.25 *
         (vertices[size_t(k[0])] + vertices[size_t(k[1])] + vertices[size_t(k[2])] + vertices[size_t(k[3])]);
}

}  // namespace pd
