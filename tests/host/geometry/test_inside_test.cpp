// The inside test (nonzero winding): exact on the grid alignments that break naive ray casting
// (rays through vertices and along shared edges), right for random points of curved shapes, the
// union where closed parts overlap and empty in a cavity.
#include <gtest/gtest.h>

#include <cmath>

#include "host/geometry/inside_test.h"
#include "host/geometry/random.h"
#include "host/geometry/shapes.h"

namespace pd {
namespace {

TEST(InsideTest, RaysThroughVerticesAndEdges) {
  // Octahedron |x| + |y| + |z| <= 1: the +x ray from (x, 0, 0) leaves through the vertex
  // (1, 0, 0), and rays with y = 0 or z = 0 run along its edges' projections.
  TriMesh octa;
  octa.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) {
        Triangle t{sx, sy, sz};
        const int flips = (sx == 1) + (sy == 3) + (sz == 5);
        if (flips % 2 == 1) std::swap(t[1], t[2]);
        octa.triangles.push_back(t);
      }
  ASSERT_GT(signed_volume(octa), 0);
  const InsideTest inside(octa);
  for (double x : {-1.5, -0.75, -0.3, 0.0, 0.3, 0.75, 1.5})
    for (double y : {-0.5, -0.25, 0.0, 0.25, 0.5})
      for (double z : {-0.5, -0.25, 0.0, 0.25, 0.5}) {
        const double s = std::fabs(x) + std::fabs(y) + std::fabs(z);
        if (s == 1) continue;  // on the surface
        EXPECT_EQ(inside.inside({x, y, z}), s < 1) << x << " " << y << " " << z;
      }
}

TEST(InsideTest, BoxDiagonalsAndGridCentres) {
  // The box's faces are split along diagonals; points with y = z lie on their projections.
  const TriMesh box = box_mesh({2, 2, 2});
  const InsideTest inside(box);
  for (int i = -12; i <= 12; ++i)
    for (int j = -12; j <= 12; ++j)
      for (int k = -12; k <= 12; ++k) {
        const Vec3d p{0.125 * i + 0.0625, 0.125 * j, 0.125 * k};
        if (std::fabs(p[1]) == 1 || std::fabs(p[2]) == 1) continue;  // on the surface
        const bool in = std::fabs(p[0]) < 1 && std::fabs(p[1]) < 1 && std::fabs(p[2]) < 1;
        ASSERT_EQ(inside.inside(p), in) << p[0] << " " << p[1] << " " << p[2];
      }
}

// Two closed boxes modelled into each other (an artist's mesh of parts): their union is inside,
// the overlap too (ray parity left it empty); a box facing inward inside another is a cavity.
TEST(InsideTest, OverlappingPartsAreTheirUnionAndACavityIsEmpty) {
  TriMesh parts = box_mesh({2, 2, 2});
  TriMesh moved = box_mesh({2, 2, 2});
  for (Vec3d& v : moved.vertices) v[0] += 1.03;  // overlapping 0.97 along x
  append(parts, moved);
  const InsideTest union_test(parts);
  for (int i = 0; i < 70; ++i)
    for (double y : {-0.9, 0.1, 0.77}) {
      const double x = -1.2 + 0.05 * i + 0.013;  // never on a face
      const bool in = x > -1 && x < 2.03;
      ASSERT_EQ(union_test.inside({x, y, 0.31}), in) << x << " " << y;
    }
  TriMesh hollow = box_mesh({2, 2, 2});
  TriMesh cavity = box_mesh({1, 1, 1});
  flip_orientation(cavity);
  append(hollow, cavity);
  const InsideTest hollow_test(hollow);
  for (int i = 0; i < 48; ++i) {
    const double x = -1.2 + 0.05 * i + 0.013;
    const bool in = std::fabs(x) < 1 && std::fabs(x) > 0.5;
    ASSERT_EQ(hollow_test.inside({x, 0.11, -0.07}), in) << x;
  }
}

TEST(InsideTest, RandomPointsOfATorus) {
  const TriMesh torus = torus_mesh(1, 0.4, 0.01);
  const InsideTest inside(torus);
  Random rng(3);
  int checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const Vec3d p{3 * rng.uniform() - 1.5, 1 * rng.uniform() - 0.5, 3 * rng.uniform() - 1.5};
    const double ring = std::hypot(p[0], p[2]) - 1;
    const double d = std::hypot(ring, p[1]) - 0.4;
    if (std::fabs(d) < 1e-3) continue;  // within the facets' chord error
    EXPECT_EQ(inside.inside(p), d < 0);
    ++checked;
  }
  EXPECT_GT(checked, 19000);
}

}  // namespace
}  // namespace pd
