// Point-in-solid test for a closed, consistently oriented triangle mesh by ray parity: the
// ray from the point along +x crosses the surface an odd number of times iff the point is
// inside. Robust on the exact alignments a particle grid produces (a ray through a vertex or
// along an edge): the ray's (y, z) is perturbed symbolically by (eps, eps^2), and each edge's
// side test is evaluated once in a canonical vertex order, so two triangles sharing an edge
// always agree about which of them the ray passes through, and the count is exact.
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

  // x of every crossing of the line (y, z) with the surface, sorted. A point (x, y, z) is
  // inside iff an odd number of them are > x (points exactly on the surface count as outside
  // on their +x side).
  void crossings(double y, double z, std::vector<double>& xs) const;

 private:
  const TriMesh* mesh_;
  Box3d box_;
  double y0_ = 0, z0_ = 0, inv_cell_ = 0;
  int ny_ = 1, nz_ = 1;
  std::vector<int64_t> bin_start_;  // CSR of triangles per (y, z) bin
  std::vector<int32_t> bin_triangles_;
};

}  // namespace pd
