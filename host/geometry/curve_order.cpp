#include "host/geometry/curve_order.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pd {
namespace {

constexpr int kBits = 21;  // cells per axis: 2^21, so three axes interleave into 63 bits

// x's low 21 bits spread to every third bit (bit b to bit 3 b).
uint64_t spread_bits(uint64_t x) {
  x &= (uint64_t(1) << kBits) - 1;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

std::vector<int32_t> morton_order(const std::vector<Vec3d>& points) {
  Box3d box;
  for (const Vec3d& p : points) box.add(p);
  const double cells = double((uint64_t(1) << kBits) - 1);
  // Cubic cells (one scale for the three axes), so the curve's locality is the same along each.
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::fmax(extent, box.hi[a] - box.lo[a]);
  const double scale = extent > 0 ? cells / extent : 0;
  // (code, index) pairs sorted: the codes' order, ties in index order, without the indirect
  // comparisons of sorting indices by their codes.
  const int64_t n = int64_t(points.size());
  std::vector<std::pair<uint64_t, int32_t>> keyed(points.size());
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < n; ++i) {
    uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double cell = std::floor((points[size_t(i)][a] - box.lo[a]) * scale);
      code |= spread_bits(uint64_t(std::clamp(cell, 0.0, cells))) << a;
    }
    keyed[size_t(i)] = {code, int32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int32_t> order(points.size());
  for (size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].second;
  return order;
}

}  // namespace pd
