#include "host/geometry/particle_geometry.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pd {

double ParticleGeometry::total_volume() const {
  return std::accumulate(volume.begin(), volume.end(), 0.0);
}

double median_nearest_distance(const ParticleGeometry& g) {
  std::vector<double> d = g.lambda;
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

void compute_lambda(ParticleGeometry& g) {
  const size_t n = g.size();
  g.lambda.assign(n, 0);
  g.min_distance = 0;
  if (n < 2) return;
  // Uniform grid of about one particle per cell, counting-sorted.
  Box3d box;
  for (const Vec3d& p : g.position) box.add(p);
  const Vec3d size = box.size();
  const double cell = std::max(1e-300, std::cbrt(std::max(size[0] * size[1] * size[2], 1e-300) / double(n)));
  int dims[3];
  for (int a = 0; a < 3; ++a) dims[a] = std::max(1, std::min(2048, int(size[a] / cell) + 1));
  auto coord = [&](const Vec3d& p, int a) {
    return std::clamp(int((p[a] - box.lo[a]) / std::max(size[a], 1e-300) * dims[a]), 0, dims[a] - 1);
  };
  auto cell_of = [&](int x, int y, int z) { return (size_t(z) * dims[1] + y) * dims[0] + x; };
  std::vector<int64_t> start(size_t(dims[0]) * dims[1] * dims[2] + 1, 0);
  for (const Vec3d& p : g.position) ++start[cell_of(coord(p, 0), coord(p, 1), coord(p, 2)) + 1];
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<int32_t> sorted(n);
  {
    std::vector<int64_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < n; ++i) {
      const Vec3d& p = g.position[i];
      sorted[size_t(fill[cell_of(coord(p, 0), coord(p, 1), coord(p, 2))]++)] = int32_t(i);
    }
  }
  double cell_side[3];
  for (int a = 0; a < 3; ++a) cell_side[a] = std::max(size[a], 1e-300) / dims[a];
  const double min_side = std::min({cell_side[0], cell_side[1], cell_side[2]});

  // Rings of cells around each particle until no closer particle can remain.
#pragma omp parallel for schedule(dynamic, 1024)
  for (int64_t i = 0; i < int64_t(n); ++i) {
    const Vec3d& p = g.position[size_t(i)];
    const int c[3] = {coord(p, 0), coord(p, 1), coord(p, 2)};
    double best2 = HUGE_VAL;
    const int max_ring = std::max({dims[0], dims[1], dims[2]});
    for (int r = 0; r <= max_ring; ++r) {
      if (best2 < HUGE_VAL && (r - 1) * min_side > 0 &&
          double(r - 1) * min_side * double(r - 1) * min_side > best2)
        break;
      for (int z = c[2] - r; z <= c[2] + r; ++z)
        for (int y = c[1] - r; y <= c[1] + r; ++y)
          for (int x = c[0] - r; x <= c[0] + r; ++x) {
            if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
            if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) continue;
            const size_t cc = cell_of(x, y, z);
            for (int64_t k = start[cc]; k < start[cc + 1]; ++k) {
              const int32_t j = sorted[size_t(k)];
              if (j != i) best2 = std::min(best2, distance2(p, g.position[size_t(j)]));
            }
          }
    }
    g.lambda[size_t(i)] = std::sqrt(best2);
  }
  g.min_distance = *std::min_element(g.lambda.begin(), g.lambda.end());
}

void set_density(ParticleGeometry& g, double density) {
  g.mass.resize(g.size());
  for (size_t i = 0; i < g.size(); ++i) g.mass[i] = density * g.volume[i];
}

}  // namespace pd
