#include "host/geometry/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace pd {
namespace {

constexpr int32_t kLeafTriangles = 4;

// Squared distance from p to the box (0 inside).
double box_distance2(const Box3d& b, const Vec3d& p) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max({b.lo[a] - p[a], 0.0, p[a] - b.hi[a]});
    d2 += d * d;
  }
  return d2;
}

}  // namespace

Vec3d closest_point_on_triangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3d bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3d cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + (vb * denom) * ab + (vc * denom) * ac;
}

MeshDistance::MeshDistance(const TriMesh& mesh) : mesh_(&mesh) {
  if (mesh.triangles.empty()) throw std::invalid_argument("MeshDistance: the mesh has no triangle");
  order_.resize(mesh.triangles.size());
  std::iota(order_.begin(), order_.end(), 0);
  for (const Triangle& t : mesh.triangles)
    centroid_.push_back((1.0 / 3) * (mesh.vertices[size_t(t[0])] + mesh.vertices[size_t(t[1])] +
                                     mesh.vertices[size_t(t[2])]));
  nodes_.reserve(2 * mesh.triangles.size() / kLeafTriangles + 1);
  build(0, int32_t(order_.size()));
}

int32_t MeshDistance::build(int32_t first, int32_t count) {
  const int32_t index = int32_t(nodes_.size());
  nodes_.push_back({});
  Box3d box, centres;
  for (int32_t k = first; k < first + count; ++k) {
    const Triangle& t = mesh_->triangles[size_t(order_[size_t(k)])];
    for (int32_t v : t) box.add(mesh_->vertices[size_t(v)]);
    centres.add(centroid_[size_t(order_[size_t(k)])]);
  }
  nodes_[size_t(index)].box = box;
  if (count <= kLeafTriangles) {
    nodes_[size_t(index)].first = first;
    nodes_[size_t(index)].count = count;
    return index;
  }
  // Split at the median centroid along the longest axis of the centroids' box.
  const Vec3d extent = centres.size();
  const int axis = extent[0] >= extent[1] && extent[0] >= extent[2] ? 0 : (extent[1] >= extent[2] ? 1 : 2);
  const int32_t half = count / 2;
  std::nth_element(
      order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
      [&](int32_t a, int32_t b) { return centroid_[size_t(a)][axis] < centroid_[size_t(b)][axis]; });
  const int32_t left = build(first, half);
  const int32_t right = build(first + half, count - half);
  nodes_[size_t(index)].left = left;
  nodes_[size_t(index)].right = right;
  return index;
}

MeshDistance::Closest MeshDistance::closest(const Vec3d& p) const {
  Closest best;
  double best2 = HUGE_VAL;
  int32_t stack[128];
  int depth = 0;
  stack[depth++] = 0;
  while (depth > 0) {
    const Node& n = nodes_[size_t(stack[--depth])];
    if (box_distance2(n.box, p) >= best2) continue;
    if (n.count > 0) {
      for (int32_t k = n.first; k < n.first + n.count; ++k) {
        const Triangle& t = mesh_->triangles[size_t(order_[size_t(k)])];
        const Vec3d q = closest_point_on_triangle(
            p, mesh_->vertices[size_t(t[0])], mesh_->vertices[size_t(t[1])], mesh_->vertices[size_t(t[2])]);
        const double d2 = distance2(p, q);
        if (d2 < best2) {
          best2 = d2;
          best.point = q;
          best.triangle = order_[size_t(k)];
        }
      }
      continue;
    }
    // The nearer child last on the stack, so it is searched first.
    const double dl = box_distance2(nodes_[size_t(n.left)].box, p),
                 dr = box_distance2(nodes_[size_t(n.right)].box, p);
    const bool left_first = dl <= dr;
    stack[depth++] = left_first ? n.right : n.left;
    stack[depth++] = left_first ? n.left : n.right;
  }
  best.distance = std::sqrt(best2);
  return best;
}

}  // namespace pd
