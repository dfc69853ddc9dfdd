#include "host/geometry/poisson_disk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "host/geometry/random.h"

namespace pd {

namespace {

// Background grid of side r / sqrt(3): at most one point per cell. Stored with a border of 2
// empty cells on every side, so the neighbour cells of any cell are at fixed index offsets. The
// (bordered) grid is cut into tiles of kTile^3 cells; a cell holds the index of its point in
// its tile's list.
constexpr int kTileShift = 4, kTile = 1 << kTileShift;

class Background {
 public:
  Background(const Box3d& box, double r) : lo_(box.lo), inv_cell_(std::sqrt(3.0) / r), r2_(r * r) {
    for (int a = 0; a < 3; ++a) {
      n_[a] = std::max<int64_t>(1, int64_t(std::ceil(box.size()[a] * inv_cell_)) + 1);
      padded_[a] = n_[a] + 4;
      tiles_[a] = (padded_[a] + kTile - 1) >> kTileShift;
    }
    cell_.assign(size_t(padded_[0] * padded_[1] * padded_[2]), -1);
    points_.resize(size_t(tiles_[0] * tiles_[1] * tiles_[2]));
    // Cells within 2 of a point's cell that can hold a point closer than r (the gap to the
    // cell, in cell sides, below sqrt 3), nearest first so conflicts are found early.
    for (int z = -2; z <= 2; ++z)
      for (int y = -2; y <= 2; ++y)
        for (int x = -2; x <= 2; ++x) {
          auto gap = [](int d) { return std::max(std::abs(d) - 1, 0); };
          const int g2 = gap(x) * gap(x) + gap(y) * gap(y) + gap(z) * gap(z);
          if (g2 < 3) offsets_.push_back({x, y, z, x * x + y * y + z * z});
        }
    std::stable_sort(offsets_.begin(), offsets_.end(),
                     [](const auto& a, const auto& b) { return a[3] < b[3]; });
    for (const auto& o : offsets_) linear_.push_back((int64_t(o[2]) * padded_[1] + o[1]) * padded_[0] + o[0]);
  }
  int64_t count(int a) const { return n_[a]; }
  int64_t tiles(int a) const { return tiles_[a]; }
  double cell_size() const { return 1 / inv_cell_; }
  // The cell of p, in bordered coordinates (the grid's cells are 2 .. n + 1); false outside the grid.
  bool coord(const Vec3d& p, int64_t c[3]) const {
    for (int a = 0; a < 3; ++a) {
      const int64_t k = int64_t(std::floor((p[a] - lo_[a]) * inv_cell_));
      if (k < 0 || k >= n_[a]) return false;
      c[a] = k + 2;
    }
    return true;
  }
  size_t index(const int64_t c[3]) const { return size_t((c[2] * padded_[1] + c[1]) * padded_[0] + c[0]); }
  size_t tile(int64_t x, int64_t y, int64_t z) const {
    return size_t(((z >> kTileShift) * tiles_[1] + (y >> kTileShift)) * tiles_[0] + (x >> kTileShift));
  }
  std::vector<Vec3d>& points(size_t tile) { return points_[tile]; }
  void put(const int64_t c[3], const Vec3d& p) {
    std::vector<Vec3d>& list = points_[tile(c[0], c[1], c[2])];
    cell_[index(c)] = int32_t(list.size());
    list.push_back(p);
  }
  bool empty(const int64_t c[3]) const { return cell_[index(c)] < 0; }
  // True when p is at least r from every stored point (cells within 2 of p's: r spans sqrt 3 cells).
  bool free(const Vec3d& p, const int64_t c[3]) const {
    const int32_t* base = cell_.data() + index(c);
    for (size_t k = 0; k < linear_.size(); ++k) {
      const int32_t q = base[linear_[k]];
      if (q < 0) continue;
      const auto& o = offsets_[k];
      if (distance2(p, points_[tile(c[0] + o[0], c[1] + o[1], c[2] + o[2])][size_t(q)]) < r2_) return false;
    }
    return true;
  }
  // Centre of a cell given in bordered coordinates.
  Vec3d center(int64_t x, int64_t y, int64_t z) const {
    const double h = cell_size();
    return {lo_[0] + (double(x - 2) + 0.5) * h, lo_[1] + (double(y - 2) + 0.5) * h,
            lo_[2] + (double(z - 2) + 0.5) * h};
  }

 private:
  Vec3d lo_;
  double inv_cell_, r2_;
  int64_t n_[3], padded_[3], tiles_[3];
  std::vector<int32_t> cell_;
  std::vector<std::vector<Vec3d>> points_;   // per tile
  std::vector<std::array<int, 4>> offsets_;  // neighbour cells: x, y, z, squared length; nearest first
  std::vector<int64_t> linear_;              // their index offsets
};

// A well-mixed 64-bit hash (splitmix64's finaliser), for independent random streams per tile.
uint64_t mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

std::vector<Vec3d> poisson_disk_points(const TriMesh& solid, const InsideTest& inside, double r,
                                       uint64_t seed) {
  const Box3d box = bounds(solid);
  Background grid(box, r);
  constexpr double kPi = 3.14159265358979323846;

  // One tile: Bridson's algorithm with its own random stream, seeded from the tile's cell
  // centres that are inside and free, its candidates kept only inside the tile.
  auto fill_tile = [&](int64_t tx, int64_t ty, int64_t tz) {
    const size_t t = grid.tile(tx << kTileShift, ty << kTileShift, tz << kTileShift);
    Random rng(mix(seed ^ mix(uint64_t(t) + 1)));
    std::vector<Vec3d>& points = grid.points(t);
    std::vector<int32_t> active;
    auto accept = [&](const Vec3d& p, const int64_t c[3]) {
      active.push_back(int32_t(points.size()));
      grid.put(c, p);
    };
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
          if (!grid.coord(p, c) || grid.tile(c[0], c[1], c[2]) != t || !grid.empty(c) || !grid.free(p, c) ||
              !inside.inside(p))
            continue;
          accept(p, c);
          placed = true;
        }
        if (!placed) {
          active[k] = active.back();
          active.pop_back();
        }
      }
    };
    std::vector<InsideTest::Crossing> xs;
    const int64_t lo[3] = {std::max<int64_t>(2, tx << kTileShift), std::max<int64_t>(2, ty << kTileShift),
                           std::max<int64_t>(2, tz << kTileShift)};
    const int64_t hi[3] = {std::min((tx + 1) << kTileShift, grid.count(0) + 2),
                           std::min((ty + 1) << kTileShift, grid.count(1) + 2),
                           std::min((tz + 1) << kTileShift, grid.count(2) + 2)};
    for (int64_t z = lo[2]; z < hi[2]; ++z)
      for (int64_t y = lo[1]; y < hi[1]; ++y) {
        const Vec3d row = grid.center(lo[0], y, z);
        inside.crossings(row[1], row[2], xs);
        if (xs.empty()) continue;
        for (int64_t x = lo[0]; x < hi[0]; ++x) {
          const Vec3d p = grid.center(x, y, z);
          const int64_t c[3] = {x, y, z};
          if (!inside_of_row(xs, p[0]) || !grid.empty(c) || !grid.free(p, c)) continue;
          accept(p, c);
          grow();
        }
      }
  };

  // Tiles in eight rounds by the parity of their coordinates: tiles of one round are at least a
  // tile (16 cells) apart, farther than any candidate looks (2 cells), so they run in parallel
  // without touching each other's cells, and the result does not depend on the thread count.
  std::vector<std::array<int64_t, 3>> round;
  for (int parity = 0; parity < 8; ++parity) {
    round.clear();
    for (int64_t z = parity >> 2 & 1; z < grid.tiles(2); z += 2)
      for (int64_t y = parity >> 1 & 1; y < grid.tiles(1); y += 2)
        for (int64_t x = parity & 1; x < grid.tiles(0); x += 2) round.push_back({x, y, z});
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t k = 0; k < int64_t(round.size()); ++k)
      fill_tile(round[size_t(k)][0], round[size_t(k)][1], round[size_t(k)][2]);
  }
  // All points, tile by tile.
  std::vector<Vec3d> points;
  for (size_t t = 0; t < size_t(grid.tiles(0) * grid.tiles(1) * grid.tiles(2)); ++t)
    points.insert(points.end(), grid.points(t).begin(), grid.points(t).end());
  return points;
}

}  // namespace pd
