// The solids of tet bodies for the ghost correction: a tet mesh's boundary is its closed,
// outward surface, and the lines of points the ghost set-up asks about are inside where the tets are.
#include <gtest/gtest.h>

#include "host/geometry/tet_body_solids.h"

namespace pd {
namespace {

// Two tets sharing a face: a bipyramid, whose boundary has six faces.
TetMesh bipyramid() {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {4, 1, 3, 2}};  // both positively oriented, sharing face (1, 2, 3)
  m.neighbors = {{1, -1, -1, -1}, {0, -1, -1, -1}};
  return m;
}

TEST(TetBodySolids, BoundaryIsTheClosedOutwardSurface) {
  const TetMesh m = bipyramid();
  ASSERT_GT(m.volume(0), 0);
  ASSERT_GT(m.volume(1), 0);
  const TriMesh surface = tet_boundary(m);
  EXPECT_EQ(surface.triangles.size(), 6u);
  EXPECT_NEAR(signed_volume(surface), m.volume(0) + m.volume(1), 1e-12);
}

TEST(TetBodySolids, LinesOfPointsAreInsideWhereTheTetsAre) {
  TetBodySolids solids;
  EXPECT_TRUE(solids.empty());
  solids.add(2, bipyramid());
  EXPECT_FALSE(solids.empty());
  EXPECT_TRUE(solids.has(2));
  EXPECT_FALSE(solids.has(0));
  EXPECT_FALSE(solids.has(3));
  // The line y = z = 0.3: inside the first tet for x in (0, 0.4) (x + y + z < 1), inside the
  // second where it continues past the shared face, up to the faces through (1, 1, 1).
  const TriMesh surface = tet_boundary(bipyramid());
  const InsideTest reference(surface);
  uint8_t inside[13];
  solids.inside_along_x(2, -0.1, 0.1, 0.3, 0.3, 13, inside);
  int count = 0;
  for (int k = 0; k < 13; ++k) {
    const double x = -0.1 + 0.1 * k;
    EXPECT_EQ(inside[k] != 0, reference.inside({x, 0.3, 0.3})) << "x = " << x;
    count += inside[k];
  }
  EXPECT_GT(count, 3);
  EXPECT_EQ(inside[0], 0);   // x = -0.1
  EXPECT_EQ(inside[12], 0);  // x = 1.1
}

}  // namespace
}  // namespace pd
