// Kernel 3 body: Levine eq. 6 quadratic repulsion.
#include <gtest/gtest.h>

#include <limits>

#include <algorithm>
#include <set>
#include <vector>

#include "cuda/kernels/collisions.h"
#include "host/random.h"

namespace pd {
namespace {

TEST(Collisions, QuadraticRepulsionBelowTheContactDistance) {
  const real rc = real(0.5e-3), kc = real(1e8);
  const Vec3 f = contact_force({real(0.3e-3), 0, 0}, {0, 0, 0}, rc, kc);
  EXPECT_NEAR(f.x, 1e8 * 0.2e-3 * 0.2e-3, 1e-5 * 4);  // K_c (d - rc)^2, pushing i away from j
  EXPECT_EQ(f.y, 0);
  const Vec3 g = contact_force({0, 0, 0}, {real(0.3e-3), 0, 0}, rc, kc);
  EXPECT_FLOAT_EQ(g.x, -f.x);
}

TEST(Collisions, NoForceAtOrBeyondTheContactDistance) {
  EXPECT_EQ(contact_force({real(1e-3), 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);
  EXPECT_EQ(contact_force({real(2e-3), 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);
  EXPECT_EQ(contact_force({0, 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);  // coincident: no direction
}

// The 8-cell search finds every point within half a cell side, like the 27-cell one, and the
// search over the sorted records finds the same points.
TEST(Collisions, HalfCellSearchFindsEveryCloseNeighbour) {
  Random rng(17);
  std::vector<Vec3> pts(3000);
  for (auto& p : pts)
    p = {real(rng.uniform() * 2 - 1), real(rng.uniform() * 2 - 1), real(rng.uniform() * 2 - 1)};
  const real cell = real(0.1);
  // Hash by sorting (bin, id), as the engine does.
  HashView h;
  h.bins = 1 << 12;
  h.inv_cell = real(1) / cell;
  std::vector<uint32_t> key(pts.size());
  std::vector<int32_t> sorted(pts.size()), start(h.bins, -1), end(h.bins, -1);
  for (size_t i = 0; i < pts.size(); ++i) key[i] = cell_bin(cell_of(pts[i], h.inv_cell), h.bins);
  for (size_t i = 0; i < pts.size(); ++i) sorted[i] = int32_t(i);
  std::stable_sort(sorted.begin(), sorted.end(), [&](int32_t a, int32_t b) { return key[a] < key[b]; });
  std::vector<uint32_t> sorted_key(pts.size());
  for (size_t s = 0; s < pts.size(); ++s) sorted_key[s] = key[sorted[s]];
  h.key = sorted_key.data();
  h.sorted = sorted.data();
  h.bin_start = start.data();
  h.bin_end = end.data();
  for (int32_t s = 0; s < int32_t(pts.size()); ++s) mark_bin_bounds(s, int32_t(pts.size()), h);
  // The sorted records the collisions kernel reads (w: a tag to check the entry).
  std::vector<Vec4> record(pts.size());
  for (size_t s = 0; s < pts.size(); ++s) record[s] = with_w(pts[size_t(sorted[s])], real(sorted[s]));
  h.record = record.data();
  auto pos = [&](int32_t j) { return pts[j]; };
  for (size_t i = 0; i < pts.size(); i += 7) {
    std::set<int32_t> half, from_records, brute;
    for_each_within_half_cell(pts[i], h, pos, [&](int32_t j) { half.insert(j); });
    for_each_record_within_half_cell(pts[i], h, [&](int32_t s, Vec4 r) {
      EXPECT_EQ(int32_t(r.w), sorted[size_t(s)]);
      from_records.insert(sorted[size_t(s)]);
    });
    for (size_t j = 0; j < pts.size(); ++j)
      if (length(pts[j] - pts[i]) < real(0.5) * cell) brute.insert(int32_t(j));
    for (int32_t j : brute) EXPECT_TRUE(half.count(j)) << i << " misses " << j;
    EXPECT_EQ(from_records, half);
  }
}

// A block of 4 x 4 x 4 cells, wherever it lies (negative coordinates too), fills 64 consecutive
// bins in Morton order; its neighbouring block starts elsewhere.
TEST(Collisions, CellBinsKeepBlocksOfCellsTogether) {
  const uint32_t bins = 1u << 16;
  for (const Cell origin : {Cell{0, 0, 0}, Cell{-8, 12, -4}, Cell{400, -4000, 36}}) {
    const uint32_t first = cell_bin(origin, bins);
    EXPECT_EQ(first % 64, 0u);
    std::set<uint32_t> seen;
    for (int z = 0; z < 4; ++z)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          const uint32_t b = cell_bin({origin.x + x, origin.y + y, origin.z + z}, bins);
          EXPECT_EQ(b - first, uint32_t(x & 1) | uint32_t(y & 1) << 1 | uint32_t(z & 1) << 2 |
                                   uint32_t(x >> 1) << 3 | uint32_t(y >> 1) << 4 | uint32_t(z >> 1) << 5);
          seen.insert(b);
        }
    EXPECT_EQ(seen.size(), 64u);
    EXPECT_NE(cell_bin({origin.x + 4, origin.y, origin.z}, bins), first + 64);
  }
}

// Runaway positions (a blow-up in progress) map to valid cells whose neighbours do not overflow.
TEST(Collisions, CellOfARunawayPositionIsClamped) {
  const real inf = std::numeric_limits<real>::infinity();
  for (real v : {real(1e30), real(-1e30), inf, -inf, std::numeric_limits<real>::quiet_NaN()}) {
    const int32_t c = cell_coord(v, real(1e3));
    EXPECT_LE(c, 1 << 30) << v;
    EXPECT_GE(c, -(1 << 30)) << v;
  }
  EXPECT_EQ(cell_coord(real(2.5e-3), real(1e3)), 2);
  EXPECT_EQ(cell_coord(real(-0.5e-3), real(1e3)), -1);
}

}  // namespace
}  // namespace pd
