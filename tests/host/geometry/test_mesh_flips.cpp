// Edge flips toward Delaunay (host/geometry/mesh_flips.h): which edges flip, and what a flip keeps.
#include "host/geometry/mesh_flips.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/geometry/mesh_check.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tet_particles.h"

namespace pd {
namespace {

// A quad a (0,0), b (1,0), c (1 + skew, h), d (skew, h) in the plane z = 0, split along a - c.
TriMesh quad(double skew, double h) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1 + skew, h, 0}, {skew, h, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

bool has_edge(const TriMesh& m, int32_t a, int32_t b) {
  for (const Triangle& t : m.triangles)
    for (int c = 0; c < 3; ++c)
      if ((t[size_t(c)] == a && t[size_t((c + 1) % 3)] == b) ||
          (t[size_t(c)] == b && t[size_t((c + 1) % 3)] == a))
        return true;
  return false;
}

TEST(MeshFlips, FlipsTheLongDiagonalOfASkewedQuad) {
  // Skewed by 0.8 at height 0.5, the diagonal a - c is long and its opposite angles are obtuse.
  TriMesh m = quad(0.8, 0.5);
  EXPECT_EQ(delaunay_flips(m, 0.1), 1);
  EXPECT_TRUE(has_edge(m, 1, 3));
  EXPECT_FALSE(has_edge(m, 0, 2));
  for (const Triangle& t : m.triangles)  // still facing +z
    EXPECT_GT(cross(m.vertices[size_t(t[1])] - m.vertices[size_t(t[0])],
                    m.vertices[size_t(t[2])] - m.vertices[size_t(t[0])])[2],
              0);
  EXPECT_EQ(delaunay_flips(m, 0.1), 0);  // Delaunay now: nothing more to do
}

TEST(MeshFlips, LeavesDelaunayEdgesAndCyclicQuads) {
  TriMesh skewed_other_way = quad(-0.8, 0.5);  // here a - c is the short diagonal
  EXPECT_EQ(delaunay_flips(skewed_other_way, 0.1), 0);
  TriMesh rectangle = quad(0, 0.5);  // both diagonals equally Delaunay: the corners on one circle
  EXPECT_EQ(delaunay_flips(rectangle, 0.1), 0);
  EXPECT_TRUE(has_edge(rectangle, 0, 2));
}

TEST(MeshFlips, LeavesEdgesWhereTheSurfaceBends) {
  // The skewed quad folded about a - c by 0.3 rad: flipping would move the surface.
  TriMesh m = quad(0.8, 0.5);
  const Vec3d a = m.vertices[0], axis = (1 / norm(m.vertices[2] - a)) * (m.vertices[2] - a);
  const Vec3d r = m.vertices[3] - a;
  const Vec3d along = dot(r, axis) * axis, across = r - along;
  m.vertices[3] = a + along + std::cos(0.3) * across + std::sin(0.3) * cross(axis, across);
  TriMesh flat_enough = m;
  EXPECT_EQ(delaunay_flips(m, 0.25), 0);
  EXPECT_EQ(delaunay_flips(flat_enough, 0.35), 1);
}

// Edges with a corner of one of their triangles at 90 degrees or more: corners inside (or on)
// the edge's diametral sphere, which TetGen splits.
int64_t encroached_edges(const TriMesh& m) {
  int64_t count = 0;
  for (const Triangle& t : m.triangles)
    for (int c = 0; c < 3; ++c) {
      const Vec3d& apex = m.vertices[size_t(t[size_t(c)])];
      const Vec3d u = m.vertices[size_t(t[size_t((c + 1) % 3)])] - apex,
                  v = m.vertices[size_t(t[size_t((c + 2) % 3)])] - apex;
      count += dot(u, v) <= 0;
    }
  return count;
}

void expect_closed_outward(TriMesh m) {
  const MeshReport r = check_solid(m, "mesh", {});
  EXPECT_FALSE(r.flipped);
  EXPECT_EQ(r.holes, 0);
  EXPECT_EQ(r.welded_vertices, 0);
}

TEST(MeshFlips, KeepClosedSolidsClosedAndTheirVolumes) {
  for (const TriMesh& shape :
       {sphere_mesh(1, 0.05), torus_mesh(1, 0.3, 0.05), vase_mesh(0.1, 0.3, 0.01, 0.006)}) {
    TriMesh m = shape;
    const int64_t flips = delaunay_flips(m, 0.25);
    expect_closed_outward(m);
    EXPECT_EQ(m.vertices, shape.vertices);
    EXPECT_EQ(m.triangles.size(), shape.triangles.size());
    EXPECT_NEAR(signed_volume(m), signed_volume(shape), 1e-3 * signed_volume(shape)) << flips << " flips";
    // The sphere's walk leaves no obtuse corner; the torus and the vase lose most of theirs
    // (152 -> 40 and 1,593 -> 1,307 edges when written).
    if (encroached_edges(shape) > 0) {
      EXPECT_GT(flips, 0);
      EXPECT_LT(encroached_edges(m), encroached_edges(shape));
    } else {
      EXPECT_EQ(flips, 0);
    }
    EXPECT_EQ(delaunay_flips(m, 0.25), 0);  // done in one call
  }
}

TEST(MeshFlips, TheVasesShellComesOutFlipped) {
  // fattened_shell flips its solid: closed, outward, and nothing left to flip.
  FattenedShell shell = fattened_shell(vase_sheet(0.1, 0.3, 0.006), 0.01, 3);
  expect_closed_outward(shell.solid);
  EXPECT_EQ(delaunay_flips(shell.solid, 0.25), 0);
}

}  // namespace
}  // namespace pd
