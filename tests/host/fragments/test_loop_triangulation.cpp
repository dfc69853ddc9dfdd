// Loops to triangles: the region's area exactly, every loop vertex used (collinear ones too),
// holes left empty, all triangles counter-clockwise.
#include "host/fragments/loop_triangulation.h"

#include <gtest/gtest.h>

#include <set>

namespace pd {
namespace {

double area_of(const std::vector<std::array<int32_t, 3>>& tris, const std::vector<Point2>& p, bool* all_ccw) {
  double a = 0;
  *all_ccw = true;
  for (const auto& t : tris) {
    const Point2 &u = p[size_t(t[0])], &v = p[size_t(t[1])], &w = p[size_t(t[2])];
    const double twice = (v.x - u.x) * (w.y - u.y) - (v.y - u.y) * (w.x - u.x);
    *all_ccw = *all_ccw && twice >= 0;
    a += 0.5 * twice;
  }
  return a;
}

TEST(LoopTriangulation, NonConvexLoopWithCollinearVertices) {
  // An L of area 3 with extra vertices in the middle of three of its edges.
  const std::vector<Point2> p = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0.5, 2}, {0, 2}, {0, 1}};
  const std::vector<std::vector<int32_t>> loops = {{0, 1, 2, 3, 4, 5, 6, 7, 8}};
  EXPECT_DOUBLE_EQ(twice_area(loops[0], p), 6);
  const auto tris = triangulate_loops(loops, p);
  bool ccw = false;
  EXPECT_DOUBLE_EQ(area_of(tris, p, &ccw), 3);
  EXPECT_TRUE(ccw);
  EXPECT_EQ(tris.size(), 7u);  // n - 2
  std::set<int32_t> used;
  for (const auto& t : tris) used.insert(t.begin(), t.end());
  EXPECT_EQ(used.size(), p.size());
}

TEST(LoopTriangulation, HoleIsBridgedAndLeftEmpty) {
  // A 4 x 4 square around a clockwise 1 x 2 hole, and a second separate triangle.
  const std::vector<Point2> p = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {1, 3},
                                 {2, 3}, {2, 1}, {5, 0}, {6, 0}, {5, 1}};
  const std::vector<std::vector<int32_t>> loops = {{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10}};
  const auto tris = triangulate_loops(loops, p);
  bool ccw = false;
  EXPECT_DOUBLE_EQ(area_of(tris, p, &ccw), 16 - 2 + 0.5);
  EXPECT_TRUE(ccw);
  std::set<int32_t> used;
  for (const auto& t : tris) used.insert(t.begin(), t.end());
  EXPECT_EQ(used.size(), p.size());
}

}  // namespace
}  // namespace pd
