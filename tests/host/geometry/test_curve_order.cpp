// Space-filling-curve order (host/geometry/curve_order.h): the Morton curve's visiting order, and
// what it is for: points near in space come near in index.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <random>

#include "host/geometry/curve_order.h"

namespace pd {
namespace {

// The 64 points of a 4 x 4 x 4 grid in a scrambled order: the curve visits them cube by cube,
// each aligned 2 x 2 x 2 cube in 8 consecutive places, the lowest corner first, x before y before z.
TEST(CurveOrder, VisitsAGridInZOrder) {
  std::vector<Vec3d> points;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) points.push_back({double(x), double(y), double(z)});
  std::shuffle(points.begin(), points.end(), std::mt19937(7));
  const std::vector<int32_t> order = morton_order(points);
  ASSERT_EQ(order.size(), 64u);
  std::vector<int32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < 64; ++k) ASSERT_EQ(sorted[size_t(k)], k) << "not a permutation";
  for (size_t k = 0; k < 64; ++k) {
    const Vec3d& p = points[size_t(order[k])];
    // Place k's bits: x in bits 0 and 3, y in 1 and 4, z in 2 and 5.
    const auto bit = [&](int b) { return double((k >> b) & 1u); };
    EXPECT_EQ(p[0], bit(0) + 2 * bit(3)) << "place " << k;
    EXPECT_EQ(p[1], bit(1) + 2 * bit(4)) << "place " << k;
    EXPECT_EQ(p[2], bit(2) + 2 * bit(5)) << "place " << k;
  }
}

TEST(CurveOrder, PointsInOneCellKeepTheirOrder) {
  const std::vector<Vec3d> points{{1, 1, 1}, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}};
  EXPECT_EQ(morton_order(points), (std::vector<int32_t>{1, 3, 0, 2}));
  EXPECT_TRUE(morton_order({}).empty());
  EXPECT_EQ(morton_order({{2, 3, 4}}), (std::vector<int32_t>{0}));
}

// Random points in a slab (one scale for all axes: the thin axis is not stretched): each point's
// nearest neighbour is, in the median, a few places away after the sort and a third of the list
// away before it.
TEST(CurveOrder, NearPointsAreNearInIndex) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3d> points(4000);
  for (Vec3d& p : points) p = {u(rng), u(rng), 0.1 * u(rng)};
  const auto median_gap = [](const std::vector<Vec3d>& pts) {
    std::vector<int64_t> gap;
    for (size_t i = 0; i < pts.size(); ++i) {
      size_t best = i == 0 ? 1 : 0;
      for (size_t j = 0; j < pts.size(); ++j)
        if (j != i && distance2(pts[j], pts[i]) < distance2(pts[best], pts[i])) best = j;
      gap.push_back(std::abs(int64_t(best) - int64_t(i)));
    }
    std::nth_element(gap.begin(), gap.begin() + long(gap.size() / 2), gap.end());
    return gap[gap.size() / 2];
  };
  const std::vector<Vec3d> sorted = permuted(points, morton_order(points));
  EXPECT_GT(median_gap(points), 500);
  EXPECT_LT(median_gap(sorted), 16);
}

}  // namespace
}  // namespace pd
