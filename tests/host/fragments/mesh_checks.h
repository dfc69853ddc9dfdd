// Checks shared by the tests of fragment surfaces: closed and consistently oriented polygon
// surfaces, their enclosed volume and area.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "host/fragments/crack_mesh_file.h"
#include "host/fragments/piece_mesh.h"

namespace pd::testing {

// Closed and consistently oriented: every directed edge of the polygons appears as often as its
// reverse; on a manifold surface exactly once each (each edge shared by exactly two faces).
// Returns the number of directed edges checked.
template <class Polygons>
size_t expect_closed(const Polygons& polygons, bool manifold, const std::string& what) {
  std::map<std::pair<int32_t, int32_t>, int> edges;
  for (const auto& p : polygons)
    for (size_t k = 0; k < p.size(); ++k) ++edges[{p[k], p[(k + 1) % p.size()]}];
  size_t bad = 0;
  for (const auto& [e, count] : edges) {
    if (manifold && count != 1) ++bad;
    const auto reverse = edges.find({e.second, e.first});
    if ((reverse == edges.end() ? 0 : reverse->second) != count) ++bad;
  }
  EXPECT_EQ(bad, 0u) << what << ": " << bad << " of " << edges.size() << " directed edges unmatched";
  return edges.size();
}

// The polygons of object o of a piece mesh.
inline std::vector<std::vector<int32_t>> object_polygons(const FragmentMesh& m, size_t o) {
  std::vector<std::vector<int32_t>> out;
  for (int64_t q = m.object_start[o]; q < m.object_start[o + 1]; ++q)
    out.emplace_back(m.polygon_vertex.begin() + m.polygon_start[size_t(q)],
                     m.polygon_vertex.begin() + m.polygon_start[size_t(q) + 1]);
  return out;
}

// Signed volume by the divergence theorem (fans of triangles from each polygon's first vertex,
// relative to `origin`): positive when the polygons face outwards.
inline double enclosed_volume(const std::vector<Vec3d>& x, const std::vector<std::vector<int32_t>>& polygons,
                              const Vec3d& origin) {
  double six_v = 0;
  for (const auto& p : polygons)
    for (size_t k = 1; k + 1 < p.size(); ++k)
      six_v += dot(x[size_t(p[0])] - origin, cross(x[size_t(p[k])] - origin, x[size_t(p[k + 1])] - origin));
  return six_v / 6;
}

inline double area(const std::vector<Vec3d>& x, const std::vector<std::vector<int32_t>>& polygons) {
  double a = 0;
  for (const auto& p : polygons)
    for (size_t k = 1; k + 1 < p.size(); ++k)
      a += 0.5 * norm(cross(x[size_t(p[k])] - x[size_t(p[0])], x[size_t(p[k + 1])] - x[size_t(p[0])]));
  return a;
}

// Closed surfaces of a triangle soup: the vertex-connected pieces, each checked to be closed and
// consistently oriented (every directed edge once, its reverse once), with its enclosed volume.
inline std::vector<double> closed_piece_volumes(const CrackSurface& s) {
  std::vector<std::vector<int32_t>> polygons;
  for (const auto& t : s.triangles) polygons.push_back({t[0], t[1], t[2]});
  expect_closed(polygons, true, "crack surface");
  std::vector<int32_t> parent(s.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int32_t i) {
    while (parent[size_t(i)] != i) i = parent[size_t(i)];
    return i;
  };
  for (const auto& t : s.triangles)
    for (int i = 1; i < 3; ++i) parent[size_t(root(t[size_t(i)]))] = root(t[0]);
  std::map<int32_t, double> volume;
  for (const auto& t : s.triangles)
    volume[root(t[0])] +=
        dot(s.vertices[size_t(t[0])], cross(s.vertices[size_t(t[1])], s.vertices[size_t(t[2])])) / 6;
  std::vector<double> out;
  for (const auto& [r, v] : volume) out.push_back(v);
  return out;
}

}  // namespace pd::testing
