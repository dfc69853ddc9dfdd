// Rays against colliders (render/collider_hit.h): each shape's entry point against its analytic
// value, turned and moved by the collider's pose; a mesh collider (sphere tracing of its distance
// grid) against the sphere it meshes; the nearest of several; planes and rays from inside unseen;
// and the renderer drawing a collider, a mesh one too, where the image had sky.
#include "render/collider_hit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/geometry/distance_grid.h"
#include "host/geometry/shapes.h"
#include "render/renderer.h"

namespace pd {
namespace {

Collider shape(ColliderShape kind, Vec3 size, Vec3 center = {0, 0, 0}) {
  Collider c;
  c.shape = kind;
  c.size = size;
  c.center = center;
  return c;
}

// Where a ray from `o` along `d` first enters `c` (NAN: never), and the normal there.
real entry(const Collider& c, Vec3 o, Vec3 d, Vec3* normal = nullptr) {
  const Collider list[1] = {c};
  real t = INFINITY;
  Vec3 n;
  const int32_t k = nearest_collider({list, 1}, make_ray(o, d, 0, INFINITY), &t, &n);
  if (normal) *normal = n;
  return k == 0 ? t : real(NAN);
}

TEST(ColliderHit, EachShapeIsEnteredWhereItsSurfaceIs) {
  const Vec3 down{0, -1, 0}, along{1, 0, 0};
  Vec3 n;
  EXPECT_NEAR(entry(shape(kColliderSphere, {1, 0, 0}), {0, 5, 0}, down, &n), 4, 1e-5);
  EXPECT_NEAR(n.y, 1, 1e-5);
  EXPECT_NEAR(entry(shape(kColliderSphere, {1, 0, 0}), {real(0.6), 5, 0}, down), 5 - std::sqrt(1 - 0.36),
              1e-5);
  EXPECT_NEAR(entry(shape(kColliderBox, {1, 2, 3}), {-5, 1, 2}, along, &n), 4, 1e-5);
  EXPECT_NEAR(n.x, -1, 1e-5);
  EXPECT_NEAR(entry(shape(kColliderCylinder, {1, 2, 0}), {-5, 1, 0}, along), 4, 1e-5);            // the side
  EXPECT_NEAR(entry(shape(kColliderCylinder, {1, 2, 0}), {real(0.5), 5, 0}, down, &n), 3, 1e-5);  // the cap
  EXPECT_NEAR(n.y, 1, 1e-5);
  EXPECT_TRUE(std::isnan(entry(shape(kColliderCylinder, {1, 2, 0}), {-5, 3, 0}, along)));  // above it
  EXPECT_NEAR(entry(shape(kColliderCapsule, {1, 2, 0}), {0, 5, 0}, down), 2, 1e-5);        // the end ball
  EXPECT_NEAR(entry(shape(kColliderCapsule, {1, 2, 0}), {-5, 1, 0}, along), 4, 1e-5);
  EXPECT_NEAR(entry(shape(kColliderCapsule, {1, 2, 0}), {-5, real(2.5), 0}, along), 5 - std::sqrt(1 - 0.25),
              1e-5);
  EXPECT_TRUE(std::isnan(entry(shape(kColliderPlane, {}), {0, 5, 0}, down)));          // not drawn
  EXPECT_TRUE(std::isnan(entry(shape(kColliderSphere, {1, 0, 0}), {0, 0, 0}, down)));  // from inside
}

// A mesh collider of a sphere of radius 1 meshed at edge 0.05, its distance grid at 0.05 (the
// grid's values appended to `grids`), at `center`.
Collider sphere_mesh_collider(std::vector<float>& grids, Vec3 center = {0, 0, 0}) {
  const DistanceGrid g = distance_grid(sphere_mesh(1, 0.05), true, 0.05, 0.2);
  Collider c = shape(kColliderMesh, {1, 1, 1}, center);
  c.grid_origin = {real(g.origin[0]), real(g.origin[1]), real(g.origin[2])};
  c.grid_cell = real(g.cell);
  for (int a = 0; a < 3; ++a) c.grid_dims[a] = g.dims[size_t(a)];
  c.grid_offset = int64_t(grids.size());
  grids.insert(grids.end(), g.distance.begin(), g.distance.end());
  return c;
}

TEST(ColliderHit, MeshIsEnteredWhereItsSurfaceIs) {
  std::vector<float> grids;
  const Collider c = sphere_mesh_collider(grids, {0, 0, 3});
  for (const real x : {real(0), real(0.5), real(-0.8)}) {
    real t = INFINITY;
    Vec3 n;
    const Collider list[1] = {c};
    ASSERT_EQ(nearest_collider({list, 1}, make_ray({x, 5, 3}, {0, -1, 0}, 0, INFINITY), &t, &n, grids.data()),
              0)
        << x;
    // Short of the surface by at most the sphere tracing's stopping distance (0.3 cells of the
    // distance, 0.3 cells / cos(incidence) along the ray), give or take the mesh's chords.
    const real cos_incidence = std::sqrt(1 - x * x);
    EXPECT_NEAR(t, 5 - cos_incidence, 0.3 * 0.05 / cos_incidence + 0.005) << x;
    EXPECT_NEAR(n.x, x, 0.06) << x;
  }
  real t = INFINITY;
  Vec3 n;
  const Collider list[1] = {c};
  EXPECT_EQ(
      nearest_collider({list, 1}, make_ray({real(1.5), 5, 3}, {0, -1, 0}, 0, INFINITY), &t, &n, grids.data()),
      -1);  // beside it
}

TEST(ColliderHit, PoseTurnsAndMovesTheShape) {
  // A 1 x 2 x 3 (half extents) box turned 90 degrees about z (its y along world -x), at (10, 0, 0).
  Collider c = shape(kColliderBox, {1, 2, 3}, {10, 0, 0});
  const real turn[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  for (int i = 0; i < 9; ++i) c.rotation[i] = turn[i];
  Vec3 n;
  EXPECT_NEAR(entry(c, {0, 0, 0}, {1, 0, 0}, &n), 8, 1e-5);  // the shape's y half extent, 2
  EXPECT_NEAR(n.x, -1, 1e-5);
  EXPECT_NEAR(entry(c, {10, 5, 0}, {0, -1, 0}), 4, 1e-5);  // its x half extent, 1
}

TEST(ColliderHit, NearestOfSeveral) {
  const Collider list[3] = {shape(kColliderSphere, {1, 0, 0}, {0, 0, -10}),
                            shape(kColliderBox, {1, 1, 1}, {0, 0, -4}),
                            shape(kColliderSphere, {1, 0, 0}, {0, 0, 10})};
  real t = INFINITY;
  Vec3 n;
  EXPECT_EQ(nearest_collider({list, 3}, make_ray({0, 0, 0}, {0, 0, -1}, 0, INFINITY), &t, &n), 1);
  EXPECT_NEAR(t, 3, 1e-5);
  t = 2;  // something nearer was already found
  EXPECT_EQ(nearest_collider({list, 3}, make_ray({0, 0, 0}, {0, 0, -1}, 0, INFINITY), &t, &n), -1);
}

TEST(ColliderHit, RendererDrawsTheColliderOverTheSky) {
  PrimitiveSet prims;
  prims.add_cube({100, 100, 100}, real(0.01));  // out of view
  RenderScene scene = make_render_scene(prims, {{1, 1, 1}});
  RenderSettings s;
  s.width = 32;
  s.height = 24;
  s.floor = false;
  Camera camera;
  camera.eye = {0, 0, 5};
  const auto renderer = make_renderer(false);
  const ImageRGB8 sky = renderer->render_frame(scene, camera, s).image;
  scene.colliders.push_back(shape(kColliderSphere, {1, 0, 0}));
  const ImageRGB8 drawn = renderer->render_frame(scene, camera, s).image;
  auto pixel = [](const ImageRGB8& im, int x, int y) {
    const size_t i = 3 * (size_t(y) * size_t(im.width) + size_t(x));
    return std::array<int, 3>{im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]};
  };
  EXPECT_NE(pixel(sky, 16, 12), pixel(drawn, 16, 12));  // the centre: the sphere
  EXPECT_EQ(pixel(sky, 0, 0), pixel(drawn, 0, 0));      // a corner: still sky
  // The same sphere as a mesh collider draws the same silhouette.
  scene.colliders = {sphere_mesh_collider(scene.collider_grids)};
  const ImageRGB8 mesh = renderer->render_frame(scene, camera, s).image;
  int differ = 0, covered = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const bool in_sphere = pixel(drawn, x, y) != pixel(sky, x, y);
      const bool in_mesh = pixel(mesh, x, y) != pixel(sky, x, y);
      covered += in_sphere;
      differ += in_sphere != in_mesh;
    }
  EXPECT_GT(covered, 20);
  EXPECT_LE(differ, 4) << "pixels covered by one of the two only (the silhouette's edge)";
}

}  // namespace
}  // namespace pd
