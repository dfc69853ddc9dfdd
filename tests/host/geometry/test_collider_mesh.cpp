// Collider surfaces (host/geometry/collider_mesh.h): closed, outward, with the shape's volume and
// centred where colliders.h puts the shape; posed by the collider's rotation and centre.
#include "host/geometry/collider_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cuda/kernels/colliders.h"
#include "host/geometry/mesh_check.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

constexpr double kPi = 3.14159265358979323846;

Collider shape(ColliderShape kind, Vec3 size) {
  Collider c;
  c.shape = kind;
  c.size = size;
  return c;
}

// Closed and outward, its volume within `tol`, and every vertex on the shape's surface (colliders.h).
void expect_surface_of(const Collider& c, double volume, double tol) {
  TriMesh m = collider_mesh(c, 0.02, 1);
  const MeshReport r = check_solid(m, "collider", {});
  EXPECT_FALSE(r.flipped);
  EXPECT_EQ(r.holes, 0);
  EXPECT_NEAR(signed_volume(m), volume, tol * volume);
  for (const Vec3d& v : m.vertices)
    EXPECT_NEAR(shape_surface(c, {real(v[0]), real(v[1]), real(v[2])}).distance, 0, 1e-6) << int(c.shape);
}

TEST(ColliderMesh, EachShapeIsClosedWithItsVolume) {
  expect_surface_of(shape(kColliderSphere, {real(0.3), 0, 0}), 4 * kPi / 3 * 0.027, 1e-2);
  expect_surface_of(shape(kColliderBox, {real(0.1), real(0.2), real(0.3)}), 8 * 0.006, 1e-6);
  expect_surface_of(shape(kColliderCylinder, {real(0.2), real(0.5), 0}), kPi * 0.04 * 1.0, 1e-2);
  expect_surface_of(shape(kColliderCapsule, {real(0.2), real(0.5), 0}),
                    kPi * 0.04 * 1.0 + 4 * kPi / 3 * 0.008, 1e-2);
}

TEST(ColliderMesh, PlaneIsASquareFacingUp) {
  const TriMesh m = collider_mesh(shape(kColliderPlane, {}), 0.1, 2);
  ASSERT_EQ(m.triangles.size(), 2u);
  for (const Triangle& t : m.triangles) {
    const Vec3d n = cross(m.vertices[size_t(t[1])] - m.vertices[size_t(t[0])],
                          m.vertices[size_t(t[2])] - m.vertices[size_t(t[0])]);
    EXPECT_GT(n[1], 0);
  }
  for (const Vec3d& v : m.vertices) EXPECT_EQ(std::abs(v[0]), 2);
}

TEST(ColliderMesh, PosedByRotationAndCentre) {
  Collider c = shape(kColliderBox, {real(0.1), real(0.2), real(0.3)});
  c.center = {1, 2, 3};
  const real turn[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};  // 90 degrees about z: x -> y
  for (int i = 0; i < 9; ++i) c.rotation[i] = turn[i];
  const TriMesh posed = posed_mesh(collider_mesh(c, 0.1, 1), c);
  for (const Vec3d& v : posed.vertices) {
    EXPECT_NEAR(std::abs(v[0] - 1), 0.2, 1e-6);  // the box's y half extent now along x
    EXPECT_NEAR(std::abs(v[1] - 2), 0.1, 1e-6);
    EXPECT_NEAR(collider_surface(c, {real(v[0]), real(v[1]), real(v[2])}).distance, 0, 1e-6);
  }
}

}  // namespace
}  // namespace pd
