#include "host/geometry/box_grid.h"

#include <algorithm>
#include <cmath>

namespace pd {

std::array<int64_t, 3> box_grid_counts(const std::array<double, 3>& size, double spacing) {
  std::array<int64_t, 3> n{};
  for (int a = 0; a < 3; ++a) n[a] = std::max<int64_t>(1, std::llround(size[a] / spacing));
  return n;
}

std::vector<Vec3> box_grid_points(const std::array<double, 3>& center, const std::array<double, 3>& size,
                                  double spacing) {
  const auto n = box_grid_counts(size, spacing);
  std::vector<Vec3> points;
  points.reserve(size_t(n[0] * n[1] * n[2]));
  auto coord = [&](int a, int64_t k) {
    return real(center[a] + (double(k) + 0.5 - 0.5 * double(n[a])) * spacing);
  };
  for (int64_t k = 0; k < n[2]; ++k)
    for (int64_t j = 0; j < n[1]; ++j)
      for (int64_t i = 0; i < n[0]; ++i) points.push_back({coord(0, i), coord(1, j), coord(2, k)});
  return points;
}

}  // namespace pd
