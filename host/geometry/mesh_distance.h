// The closest point of a triangle mesh to a query point, through a bounding-volume hierarchy of its
// triangles (median splits, leaves of a few triangles, nearer child first, boxes farther than the
// best so far skipped): for building a mesh collider's distance grid without a loop over every
// triangle per grid node.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3d closest_point_on_triangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

class MeshDistance {
 public:
  // `mesh` must outlive the query object and have at least one triangle.
  explicit MeshDistance(const TriMesh& mesh);

  struct Closest {
    double distance = 0;  // unsigned [m]
    Vec3d point{0, 0, 0};
    int32_t triangle = -1;
  };
  Closest closest(const Vec3d& p) const;

 private:
  struct Node {
    Box3d box;
    int32_t first = 0, count = 0;  // a leaf's triangles in order_; count 0: an inner node
    int32_t left = 0, right = 0;
  };
  int32_t build(int32_t first, int32_t count);

  const TriMesh* mesh_;
  std::vector<int32_t> order_;  // triangles, grouped by leaf
  std::vector<Vec3d> centroid_;
  std::vector<Node> nodes_;
};

}  // namespace pd
