#include "host/geometry/tet_mesh.h"

#include <cstdint>

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

std::vector<std::array<int32_t, 4>> face_neighbors(const std::vector<std::array<int32_t, 4>>& tets,
                                                   size_t vertex_count) {
  // The tets around each vertex, in tet order (a CSR table: first[v] .. first[v + 1]).
  std::vector<int64_t> first(vertex_count + 1, 0);
  for (const auto& t : tets)
    for (int32_t v : t) ++first[size_t(v) + 1];
  for (size_t v = 0; v < vertex_count; ++v) first[v + 1] += first[v];
  std::vector<int32_t> around(size_t(first[vertex_count]));
  std::vector<int64_t> fill(first.begin(), first.end() - 1);
  for (size_t t = 0; t < tets.size(); ++t)
    for (int32_t v : tets[t]) around[size_t(fill[size_t(v)]++)] = int32_t(t);

  // Face k's other tet: among the tets around its vertex with the fewest, the one (not t) that
  // holds the face's other two vertices. Each tet's row is written by its own iteration alone.
  std::vector<std::array<int32_t, 4>> across(tets.size());
  const int64_t n = int64_t(tets.size());
#pragma omp parallel for schedule(static)
  for (int64_t t = 0; t < n; ++t) {
    const auto& c = tets[size_t(t)];
    for (int k = 0; k < 4; ++k) {
      int32_t face[3], m = 0;
      for (int q = 0; q < 4; ++q)
        if (q != k) face[m++] = c[size_t(q)];
      auto count = [&](int32_t v) { return first[size_t(v) + 1] - first[size_t(v)]; };
      int pivot = 0;
      for (int q = 1; q < 3; ++q)
        if (count(face[q]) < count(face[pivot])) pivot = q;
      const int32_t b = face[(pivot + 1) % 3], d = face[(pivot + 2) % 3];
      int32_t other = -1;
      for (int64_t r = first[size_t(face[pivot])]; r < first[size_t(face[pivot]) + 1]; ++r) {
        const int32_t u = around[size_t(r)];
        if (u == int32_t(t)) continue;
        const auto& e = tets[size_t(u)];
        bool has_b = false, has_d = false;
        for (int32_t w : e) {
          has_b |= w == b;
          has_d |= w == d;
        }
        if (has_b && has_d) {
          other = u;
          break;
        }
      }
      across[size_t(t)][size_t(k)] = other;
    }
  }
  return across;
}

}  // namespace pd
