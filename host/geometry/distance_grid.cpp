#include "host/geometry/distance_grid.h"

#include <cmath>
#include <limits>

#include "host/geometry/inside_test.h"
#include "host/geometry/mesh_distance.h"

namespace pd {
namespace {

std::array<int32_t, 3> grid_dims(const Box3d& box, double cell, double margin) {
  std::array<int32_t, 3> dims;
  for (int a = 0; a < 3; ++a)
    dims[size_t(a)] = int32_t(std::ceil((box.hi[a] - box.lo[a] + 2 * margin) / cell)) + 1;
  return dims;
}

}  // namespace

int64_t distance_grid_nodes(const TriMesh& mesh, double cell, double margin) {
  // Counted in floating point: a tiny cell's counts overflow the grid's 32-bit dimensions.
  const Box3d box = bounds(mesh);
  double nodes = 1;
  for (int a = 0; a < 3; ++a) nodes *= std::ceil((box.hi[a] - box.lo[a] + 2 * margin) / cell) + 1;
  return nodes < 9e18 ? int64_t(nodes) : std::numeric_limits<int64_t>::max();
}

DistanceGrid distance_grid(const TriMesh& mesh, bool closed, double cell, double margin) {
  const Box3d box = bounds(mesh);
  DistanceGrid g;
  g.cell = cell;
  g.solid = closed;
  g.dims = grid_dims(box, cell, margin);
  // Centre the grid on the box, so the margin is even on both sides.
  for (int a = 0; a < 3; ++a) g.origin[size_t(a)] = box.center()[a] - 0.5 * cell * (g.dims[size_t(a)] - 1);
  const int64_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  g.distance.resize(size_t(nx * ny * nz));
  const MeshDistance nearest(mesh);
  const InsideTest* inside = nullptr;
  InsideTest tester(mesh);
  if (closed) inside = &tester;
    // One (y, z) row at a time: its crossings with the surface give each node's side.
#pragma omp parallel for schedule(dynamic, 4)
  for (int64_t row = 0; row < ny * nz; ++row) {
    const int64_t j = row % ny, k = row / ny;
    const double y = g.origin[1] + cell * double(j), z = g.origin[2] + cell * double(k);
    std::vector<InsideTest::Crossing> xs;
    if (inside) inside->crossings(y, z, xs);
    RowWalk walk(xs);
    for (int64_t i = 0; i < nx; ++i) {
      const double x = g.origin[0] + cell * double(i);
      double d = nearest.closest({x, y, z}).distance;
      if (inside && walk.inside(x)) d = -d;
      g.distance[size_t(i + nx * (j + ny * k))] = float(d);
    }
  }
  return g;
}

}  // namespace pd
