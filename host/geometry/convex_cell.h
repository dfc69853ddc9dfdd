// A convex polytope cut by half-spaces, for Voronoi cells: starts as a box and keeps the side
// n.x <= d of each plane it is clipped by. Crossings of an edge are computed once and shared by
// its two faces, so the faces stay a closed, consistently oriented (outward) surface.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/vec3d.h"

namespace pd {

class ConvexCell {
 public:
  struct Face {
    Vec3d normal;                  // outward unit normal
    double offset;                 // the face's plane: normal . x = offset
    int32_t id;                    // caller's label (a neighbour site, or a box side)
    std::vector<int32_t> corners;  // counter-clockwise seen from outside
  };

  // The box [lo, hi]; its sides get ids -1 - (2 axis + (0 low, 1 high)).
  ConvexCell(const Vec3d& lo, const Vec3d& hi);
  // Back to the box [lo, hi], keeping the allocated memory (one cell object serves many sites).
  void reset(const Vec3d& lo, const Vec3d& hi);

  // Keeps n.x <= d (n need not be unit length). Returns false when the plane does not cut.
  bool clip(const Vec3d& n, double d, int32_t id);

  // Largest distance from `p` to a corner.
  double max_distance(const Vec3d& p) const;
  // Volume by a fan of tetrahedra from `inner`, a point inside.
  double volume(const Vec3d& inner) const;
  void bounds(Vec3d& lo, Vec3d& hi) const;

  const std::vector<Face>& faces() const { return faces_; }
  const Vec3d& corner(int32_t v) const { return vertices_[size_t(v)]; }
  bool empty() const { return faces_.empty(); }

 private:
  void update_live();
  Face new_face(const Vec3d& n, double d, int32_t id);  // reuses a spare face's corner buffer

  std::vector<Vec3d> vertices_;  // corners; those of removed parts stay unused
  std::vector<Face> faces_;
  std::vector<int32_t> live_;   // corners of the current faces, each once
  std::vector<uint32_t> mark_;  // scratch: the last update_live that listed each corner
  uint32_t epoch_ = 0;
  std::vector<double> side_;  // scratch: signed distances
  std::vector<Face> kept_;    // scratch: the faces being rebuilt
  std::vector<Face> spare_;   // removed faces, whose corner buffers are reused
  std::vector<int32_t> scratch_corners_;
  std::vector<std::pair<uint64_t, int32_t>> crossing_;  // scratch: edge -> its crossing corner
  std::vector<std::pair<int32_t, int32_t>> cap_next_;   // scratch: the new face's corner links
};

// Keeps the part of the convex polygon `poly` with n.x <= d (the polygon is rebuilt in
// `scratch`, then swapped into `poly`).
void clip_polygon(std::vector<Vec3d>& poly, const Vec3d& n, double d, std::vector<Vec3d>& scratch);

}  // namespace pd
