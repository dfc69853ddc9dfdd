#include "host/geometry/mesh_flips.h"

#include <cmath>
#include <unordered_map>
#include <vector>

namespace pd {

namespace {

constexpr int kMaxPasses = 16;  // a cap: on a curved surface the flips need not settle

uint64_t edge_key(int32_t a, int32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

double angle_at(const Vec3d& apex, const Vec3d& p, const Vec3d& q) {
  const Vec3d u = p - apex, v = q - apex;
  return std::atan2(norm(cross(u, v)), dot(u, v));
}

Vec3d normal_of(const TriMesh& mesh, const Triangle& t) {
  const auto& x = mesh.vertices;
  return cross(x[size_t(t[1])] - x[size_t(t[0])], x[size_t(t[2])] - x[size_t(t[0])]);
}

// The corner of triangle t after the directed edge a -> b (its third vertex), or -1 where t does
// not hold a -> b.
int32_t after_edge(const Triangle& t, int32_t a, int32_t b) {
  for (int c = 0; c < 3; ++c)
    if (t[size_t(c)] == a && t[size_t((c + 1) % 3)] == b) return t[size_t((c + 2) % 3)];
  return -1;
}

}  // namespace

int64_t delaunay_flips(TriMesh& mesh, double max_dihedral) {
  // Each edge's triangles: two for an interior edge of a manifold surface.
  std::unordered_map<uint64_t, std::vector<int32_t>> sides;
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int c = 0; c < 3; ++c)
      sides[edge_key(mesh.triangles[f][size_t(c)], mesh.triangles[f][size_t((c + 1) % 3)])].push_back(
          int32_t(f));
  const double min_cos = std::cos(max_dihedral);
  auto move_edge = [&](int32_t a, int32_t b, int32_t from, int32_t to) {
    for (int32_t& f : sides[edge_key(a, b)])
      if (f == from) f = to;
  };
  int64_t flips = 0;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    std::vector<uint64_t> keys;
    keys.reserve(sides.size());
    for (const auto& [key, faces] : sides)
      if (faces.size() == 2) keys.push_back(key);
    int64_t flipped = 0;
    for (const uint64_t key : keys) {
      const auto it = sides.find(key);
      if (it == sides.end() || it->second.size() != 2) continue;
      // t1 holds a -> b (corner c after it), t2 holds b -> a (corner d)
      const int32_t lo = int32_t(key >> 32), hi = int32_t(key & 0xffffffffu);
      int32_t t1 = it->second[0], t2 = it->second[1], a = lo, b = hi;
      if (after_edge(mesh.triangles[size_t(t1)], a, b) < 0) std::swap(a, b);
      const int32_t c = after_edge(mesh.triangles[size_t(t1)], a, b);
      const int32_t d = after_edge(mesh.triangles[size_t(t2)], b, a);
      if (c < 0 || d < 0 || c == d || sides.count(edge_key(c, d))) continue;  // not a flippable pair
      const auto& x = mesh.vertices;
      const Vec3d &pa = x[size_t(a)], &pb = x[size_t(b)], &pc = x[size_t(c)], &pd = x[size_t(d)];
      if (angle_at(pc, pa, pb) + angle_at(pd, pa, pb) <= M_PI * (1 + 1e-12)) continue;  // locally Delaunay
      const Vec3d n1 = normal_of(mesh, mesh.triangles[size_t(t1)]),
                  n2 = normal_of(mesh, mesh.triangles[size_t(t2)]);
      if (dot(n1, n2) < min_cos * norm(n1) * norm(n2))
        continue;                                   // too bent to flip without moving the surface
      const Triangle new1{a, d, c}, new2{d, b, c};  // the quad a -> d -> b -> c split along c - d
      const Vec3d facing = n1 + n2;
      if (!(dot(normal_of(mesh, new1), facing) > 0) || !(dot(normal_of(mesh, new2), facing) > 0)) continue;
      mesh.triangles[size_t(t1)] = new1;
      mesh.triangles[size_t(t2)] = new2;
      sides.erase(it);
      sides[edge_key(c, d)] = {t1, t2};
      move_edge(a, d, t2, t1);
      move_edge(b, c, t1, t2);
      ++flipped;
    }
    flips += flipped;
    if (flipped == 0) break;
  }
  return flips;
}

}  // namespace pd
