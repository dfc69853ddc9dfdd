// Point-in-solid test for a closed triangle mesh by the nonzero winding rule: the ray from the
// point along +x crosses the surface; each crossing counts +1 where the surface faces +x (the ray
// leaves a part there) and -1 where it faces -x, and the point is inside iff the sum is not zero.
// For a closed, consistently oriented mesh without self-intersections this is ray parity; where
// closed parts overlap or cross (two shells modelled into each other, a limb through a body) the
// overlap is inside, the parts' union, and a cavity (a part facing inward) stays empty. Robust on
// the exact alignments a particle grid produces (a ray through a vertex or along an edge): the
// ray's (y, z) is perturbed symbolically by (eps, eps^2), and each edge's side test is evaluated
// once in a canonical vertex order, so two triangles sharing an edge always agree about which of
// them the ray passes through, and the count is exact.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

class InsideTest {
 public:
  // `mesh` must outlive the tester and be closed (see check_solid).
  explicit InsideTest(const TriMesh& mesh);

  bool inside(const Vec3d& p) const;

  // One crossing of a line (y, z) with the surface: its x, and +1 where the surface faces +x
  // there, -1 where it faces -x.
  struct Crossing {
    double x;
    int sign;
  };
  // Every crossing of the line (y, z) with the surface, sorted by x. A point (x, y, z) is inside
  // iff the signs of the crossings beyond it (> x) do not sum to zero (points exactly on the
  // surface count as outside on their +x side): `inside_of_row`, or `RowWalk` along the row.
  void crossings(double y, double z, std::vector<Crossing>& xs) const;

 private:
  const TriMesh* mesh_;
  Box3d box_;
  double y0_ = 0, z0_ = 0, inv_cell_ = 0;
  int ny_ = 1, nz_ = 1;
  std::vector<int64_t> bin_start_;  // CSR of triangles per (y, z) bin
  std::vector<int32_t> bin_triangles_;
};

// Whether the point at x of a row is inside, from the row's crossings.
bool inside_of_row(const std::vector<InsideTest::Crossing>& xs, double x);

// The points of a row in order of increasing x: `inside(x)` for x never decreasing.
class RowWalk {
 public:
  explicit RowWalk(const std::vector<InsideTest::Crossing>& xs);
  bool inside(double x);

 private:
  const std::vector<InsideTest::Crossing>& xs_;
  size_t next_ = 0;  // the first crossing beyond the last x
  int winding_ = 0;  // the signs' sum from next_ on
};

}  // namespace pd
