// Mesh distances (host/geometry/mesh_distance.h, distance_grid.h): the BVH's closest point against
// a loop over every triangle; the grid's nodes against brute force and the inside test, signed for
// a closed mesh and unsigned for an open sheet; and the trilinear field the kernels read
// (cuda/kernels/colliders.h) between the nodes.
#include "host/geometry/distance_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cuda/kernels/colliders.h"
#include "host/geometry/inside_test.h"
#include "host/geometry/mesh_distance.h"
#include "host/geometry/shapes.h"

namespace pd {
namespace {

double brute_force_distance(const TriMesh& m, const Vec3d& p) {
  double best = HUGE_VAL;
  for (const Triangle& t : m.triangles)
    best = std::min(best, std::sqrt(distance2(p, closest_point_on_triangle(p, m.vertices[size_t(t[0])],
                                                                           m.vertices[size_t(t[1])],
                                                                           m.vertices[size_t(t[2])]))));
  return best;
}

TEST(MeshDistance, ClosestPointOfATriangleInEachRegion) {
  const Vec3d a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  auto expect = [&](Vec3d p, Vec3d q) {
    const Vec3d got = closest_point_on_triangle(p, a, b, c);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[size_t(i)], q[size_t(i)], 1e-12);
  };
  expect({-1, -1, 1}, a);  // beyond a corner
  expect({2, -1, 0}, b);
  expect({0.5, -1, 3}, {0.5, 0, 0});          // beyond an edge
  expect({1, 1, 0}, {0.5, 0.5, 0});           // beyond the hypotenuse
  expect({0.25, 0.25, -2}, {0.25, 0.25, 0});  // above the face
}

TEST(MeshDistance, AgreesWithALoopOverEveryTriangle) {
  const TriMesh torus = torus_mesh(1, 0.3, 0.1);
  const MeshDistance query(torus);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 300; ++k) {
    const Vec3d p{u(rng), u(rng), u(rng)};
    EXPECT_NEAR(query.closest(p).distance, brute_force_distance(torus, p), 1e-12);
  }
}

TEST(DistanceGrid, ClosedMeshIsSignedAtEveryNode) {
  const TriMesh torus = torus_mesh(1, 0.3, 0.1);
  const DistanceGrid g = distance_grid(torus, true, 0.1, 0.2);
  EXPECT_TRUE(g.solid);
  const InsideTest inside(torus);
  int64_t negative = 0;
  for (int32_t k = 0; k < g.dims[2]; k += 3)
    for (int32_t j = 0; j < g.dims[1]; ++j)
      for (int32_t i = 0; i < g.dims[0]; i += 2) {
        const Vec3d p{g.origin[0] + g.cell * i, g.origin[1] + g.cell * j, g.origin[2] + g.cell * k};
        const double d = brute_force_distance(torus, p);
        const float got = g.distance[size_t(i + g.dims[0] * (j + g.dims[1] * k))];
        EXPECT_NEAR(got, inside.inside(p) ? -d : d, 1e-5 + 1e-6 * d);
        negative += got < 0;
      }
  EXPECT_GT(negative, 0);
  // The grid covers the box and the margin.
  EXPECT_LE(g.origin[0], -1.3 - 0.2 + 1e-9);
  EXPECT_GE(g.origin[0] + g.cell * (g.dims[0] - 1), 1.3 + 0.2 - 1e-9);
}

TEST(DistanceGrid, OpenSheetIsUnsigned) {
  TriMesh sheet;  // a unit square in the x-z plane
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  sheet.triangles = {{0, 2, 1}, {0, 3, 2}};
  const DistanceGrid g = distance_grid(sheet, false, 0.125, 0.25);
  EXPECT_FALSE(g.solid);
  for (float d : g.distance) EXPECT_GE(d, 0);
}

TEST(DistanceGrid, KernelsInterpolateItBetweenTheNodes) {
  // A sphere of radius 1 (fine mesh): the trilinear field between nodes of 0.05 is within a few
  // thousandths of the exact |x| - 1 near the surface, with the normal along x.
  const TriMesh sphere = sphere_mesh(1, 0.02);
  const DistanceGrid g = distance_grid(sphere, true, 0.05, 0.1);
  Collider c;
  c.shape = kColliderMesh;
  c.grid_origin = {real(g.origin[0]), real(g.origin[1]), real(g.origin[2])};
  c.grid_cell = real(g.cell);
  for (int a = 0; a < 3; ++a) c.grid_dims[a] = g.dims[size_t(a)];
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> r(0.9, 1.1);
  for (int k = 0; k < 200; ++k) {
    Vec3d dir{n(rng), n(rng), n(rng)};
    dir = (1 / norm(dir)) * dir;
    const double radius = r(rng);
    const SurfacePoint s = shape_surface(
        c, {real(radius * dir[0]), real(radius * dir[1]), real(radius * dir[2])}, g.distance.data());
    EXPECT_NEAR(s.distance, radius - 1, 3e-3);
    EXPECT_GT(double(s.normal.x) * dir[0] + double(s.normal.y) * dir[1] + double(s.normal.z) * dir[2], 0.99);
  }
  // Outside the grid: the distance keeps growing.
  EXPECT_NEAR(shape_surface(c, {3, 0, 0}, g.distance.data()).distance, 2, 1e-2);
}

}  // namespace
}  // namespace pd
