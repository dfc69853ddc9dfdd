#include "poisson_disk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "../random.h"

namespace pd {

namespace {

// Background grid of side r / sqrt(3): at most one point per cell. Stored with a border of 2
// empty cells on every side, so the neighbour cells of any cell are at fixed index offsets.
class Background {
 public:
  Background(const Box3d& box, double r) : lo_(box.lo), inv_cell_(std::sqrt(3.0) / r), r2_(r * r) {
    for (int a = 0; a < 3; ++a) {
      n_[a] = std::max<int64_t>(1, int64_t(std::ceil(box.size()[a] * inv_cell_)) + 1);
      padded_[a] = n_[a] + 4;
    }
    cell_.assign(size_t(padded_[0] * padded_[1] * padded_[2]), -1);
    // Cells within 2 of a point's cell that can hold a point closer than r (the gap to the
    // cell, in cell sides, below sqrt 3), nearest first so conflicts are found early.
    std::vector<std::array<int, 4>> offsets;
    for (int z = -2; z <= 2; ++z)
      for (int y = -2; y <= 2; ++y)
        for (int x = -2; x <= 2; ++x) {
          auto gap = [](int d) { return std::max(std::abs(d) - 1, 0); };
          const int g2 = gap(x) * gap(x) + gap(y) * gap(y) + gap(z) * gap(z);
          if (g2 < 3) offsets.push_back({x, y, z, x * x + y * y + z * z});
        }
    std::stable_sort(offsets.begin(), offsets.end(),
                     [](const auto& a, const auto& b) { return a[3] < b[3]; });
    for (const auto& o : offsets) offsets_.push_back((int64_t(o[2]) * padded_[1] + o[1]) * padded_[0] + o[0]);
  }
  int64_t count(int a) const { return n_[a]; }
  double cell_size() const { return 1 / inv_cell_; }
  bool coord(const Vec3d& p, int64_t c[3]) const {
    for (int a = 0; a < 3; ++a) {
      c[a] = int64_t(std::floor((p[a] - lo_[a]) * inv_cell_));
      if (c[a] < 0 || c[a] >= n_[a]) return false;
    }
    return true;
  }
  size_t index(const int64_t c[3]) const {
    return size_t(((c[2] + 2) * padded_[1] + c[1] + 2) * padded_[0] + c[0] + 2);
  }
  int32_t& at(const int64_t c[3]) { return cell_[index(c)]; }
  // True when p is at least r from every stored point (cells within 2 of p's: r spans sqrt 3 cells).
  bool free(const Vec3d& p, const int64_t c[3], const std::vector<Vec3d>& points) const {
    const int32_t* base = cell_.data() + index(c);
    for (const int64_t o : offsets_) {
      const int32_t q = base[o];
      if (q >= 0 && distance2(p, points[size_t(q)]) < r2_) return false;
    }
    return true;
  }
  Vec3d center(int64_t x, int64_t y, int64_t z) const {
    const double h = cell_size();
    return {lo_[0] + (double(x) + 0.5) * h, lo_[1] + (double(y) + 0.5) * h, lo_[2] + (double(z) + 0.5) * h};
  }

 private:
  Vec3d lo_;
  double inv_cell_, r2_;
  int64_t n_[3], padded_[3];
  std::vector<int32_t> cell_;
  std::vector<int64_t> offsets_;  // index offsets of the neighbour cells, nearest first
};

}  // namespace

std::vector<Vec3d> poisson_disk_points(const TriMesh& solid, const InsideTest& inside, double r,
                                       uint64_t seed) {
  const Box3d box = bounds(solid);
  Background grid(box, r);
  Random rng(seed);
  std::vector<Vec3d> points;
  std::vector<int32_t> active;
  constexpr double kPi = 3.14159265358979323846;

  auto accept = [&](const Vec3d& p, const int64_t c[3]) {
    grid.at(c) = int32_t(points.size());
    active.push_back(int32_t(points.size()));
    points.push_back(p);
  };
  // Grows the sample from the active points until none can place a neighbour.
  auto grow = [&] {
    while (!active.empty()) {
      const size_t k = size_t(rng.next_u64() % active.size());
      const Vec3d origin = points[size_t(active[k])];
      bool placed = false;
      for (int attempt = 0; attempt < 30 && !placed; ++attempt) {
        // Uniform in the spherical shell [r, 2r].
        const double u = rng.uniform(), cos_t = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform();
        const double radius = r * std::cbrt(1 + 7 * u);
        const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
        const Vec3d p = origin + radius * Vec3d{sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
        int64_t c[3];
        if (!grid.coord(p, c) || grid.at(c) >= 0 || !grid.free(p, c, points) || !inside.inside(p)) continue;
        accept(p, c);
        placed = true;
      }
      if (!placed) {
        active[k] = active.back();
        active.pop_back();
      }
    }
  };
  // Seeds: background cell centres that are inside and free, in grid order.
  std::vector<double> xs;
  for (int64_t z = 0; z < grid.count(2); ++z)
    for (int64_t y = 0; y < grid.count(1); ++y) {
      const Vec3d row = grid.center(0, y, z);
      inside.crossings(row[1], row[2], xs);
      if (xs.empty()) continue;
      for (int64_t x = 0; x < grid.count(0); ++x) {
        const Vec3d p = grid.center(x, y, z);
        const size_t beyond = size_t(xs.end() - std::upper_bound(xs.begin(), xs.end(), p[0]));
        int64_t c[3];
        if (beyond % 2 == 0 || !grid.coord(p, c) || grid.at(c) >= 0 || !grid.free(p, c, points)) continue;
        accept(p, c);
        grow();
      }
    }
  return points;
}

}  // namespace pd
