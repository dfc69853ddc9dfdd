// Glass through touching elements (render/union_walk.h, render/glass.h): a slab of touching
// cubes bends a ray only at its two outer faces, so the ray leaves parallel to how it came, moved
// sideways by the slab's refraction shift; a crack wider than the union tolerance is a real
// interface.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "host/geometry/random.h"
#include "render/glass.h"
#include "render/primitive_set.h"
#include "render/traverse.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

constexpr real kIor = real(1.5);

struct SlabResult {
  Vec3 entry, inside_dir;
  GlassTransit out;
};

// The ray from `o` along unit `d` enters the scene (refracting) and crosses the glass.
SlabResult cross_slab(const PrimitiveSet& scene, Vec3 o, Vec3 d, real gap) {
  const KdTree tree = build_kdtree(scene.bounds());
  const PrimitivesView v = scene.view();
  const Hit hit = traverse_full_stack(tree.view(), v, make_ray(o, d, 0, INFINITY));
  EXPECT_GE(hit.prim, 0);
  SlabResult r;
  r.entry = o + hit.t * d;
  const Fresnel f = fresnel_dielectric(-dot(d, hit.normal), 1, kIor);
  r.inside_dir = refract(d, hit.normal, 1, kIor, f.cos_t);
  r.out = glass_transit(tree.view(), v, r.entry, r.inside_dir, hit.prim, kIor, gap);
  return r;
}

// A block of nx x ny x nz cubes of side s (centres at multiples of s), optionally each moved by
// up to `jitter` on every axis (small gaps and overlaps between neighbours).
PrimitiveSet block(int nx, int ny, int nz, real s, real jitter, uint64_t seed) {
  Random rng(seed);
  PrimitiveSet p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        p.add_cube(Vec3{i * s, j * s, k * s} + testing::uniform_point(rng, -jitter, jitter), s / 2);
  return p;
}

// Checks the slab result for a slab of thickness `thick` between y = top and y = top - thick.
void expect_parallel_shift(const SlabResult& r, Vec3 d, real top, real thick, int min_elements) {
  ASSERT_GE(r.out.last, 0);
  EXPECT_EQ(r.out.internal_reflections, 0);
  EXPECT_GE(r.out.elements, min_elements);  // crossed several touching cubes without refracting
  EXPECT_NEAR(r.entry.y, top, 1e-5);
  EXPECT_NEAR(r.out.point.y, top - thick, 1e-4);  // left through the bottom face, the only other refraction
  // Parallel to the incoming ray.
  EXPECT_NEAR(r.out.dir.x, d.x, 2e-5);
  EXPECT_NEAR(r.out.dir.y, d.y, 2e-5);
  EXPECT_NEAR(r.out.dir.z, d.z, 2e-5);
  // Displaced sideways by thick sin(theta_i - theta_t) / cos(theta_t).
  const double ti = std::acos(-d.y), tt = std::asin(std::sin(ti) / kIor);
  const double shift = thick * std::sin(ti - tt) / std::cos(tt);
  const Vec3 straight = r.out.point - r.entry;
  const Vec3 perp = straight - dot(straight, d) * d;
  EXPECT_NEAR(length(perp), shift, 1e-4);
  EXPECT_GT(shift, 0.01);
}

TEST(Glass, SlabOfTouchingCubesRefractsOnlyAtItsOuterFaces) {
  const real s = real(0.125);  // dyadic: neighbouring faces coincide exactly
  const PrimitiveSet slab = block(10, 3, 10, s, 0, 1);
  const real top = 2.5f * s, thick = 3 * s;
  for (const double angle : {0.3, 0.6, 0.9}) {
    const Vec3 d = normalize(Vec3{real(std::sin(angle)), real(-std::cos(angle)), real(0.2)});
    const Vec3 o = Vec3{real(0.4), top, real(0.5)} - real(2) * d;
    expect_parallel_shift(cross_slab(slab, o, d, real(0.005) * s), d, top, thick, 3);
  }
}

TEST(Glass, SmallGapsBetweenElementsAreJoined) {
  // Spacing 0.1 (faces off by ulps) and cubes moved by up to 0.05% of the side: gaps and
  // overlaps far below the union tolerance of 0.5%.
  const real s = real(0.1);
  const PrimitiveSet slab = block(10, 4, 10, s, real(0.0005) * s, 2);
  const real thick = 4 * s;
  const Vec3 d = normalize(Vec3{real(0.5), real(-0.8), real(-0.1)});
  const Vec3 o = Vec3{real(0.3), 3.5f * s, real(0.6)} - real(1) * d;  // aimed at the top face
  const SlabResult r = cross_slab(slab, o, d, real(0.005) * s);
  // The top and bottom faces are where the jittered cubes put them: compare with the hit layers.
  expect_parallel_shift(r, d, r.entry.y, r.entry.y - r.out.point.y, 4);
  EXPECT_NEAR(r.entry.y - r.out.point.y, thick, 0.002 * s);
}

TEST(Glass, ACrackWiderThanTheToleranceIsAnInterface) {
  // Two slabs with a crack of 2% of the side between them: the light leaves the upper one.
  const real s = real(0.125);
  PrimitiveSet p = block(8, 2, 8, s, 0, 3);
  const real crack = real(0.02) * s;
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 8; ++i) p.add_cube({i * s, -s - crack, k * s}, s / 2);
  const Vec3 d = normalize(Vec3{real(0.4), real(-1), 0});
  const Vec3 o = Vec3{real(0.4), 1.5f * s, real(0.5)} - real(2) * d;
  const SlabResult r = cross_slab(p, o, d, real(0.005) * s);
  ASSERT_GE(r.out.last, 0);
  EXPECT_NEAR(r.out.point.y, -0.5f * s, 1e-5);  // the upper slab's bottom face
  EXPECT_LT(r.out.last, 128);                   // one of the upper slab's cubes
  EXPECT_NEAR(r.out.dir.x, d.x, 2e-5);
}

TEST(Glass, TotalInternalReflectionKeepsTheLightInside) {
  // A tall column of touching cubes entered through its top: light refracted steeply enough hits
  // the side walls beyond the critical angle and reflects until it reaches the bottom.
  const real s = real(0.125);
  const PrimitiveSet column = block(2, 16, 2, s, 0, 4);
  const Vec3 d = normalize(Vec3{real(0.9), real(-0.3), 0});
  const Vec3 o = Vec3{real(0.02), 15.5f * s, real(0.06)} - real(0.5) * d;
  const SlabResult r = cross_slab(column, o, d, real(0.005) * s);
  ASSERT_GE(r.out.last, 0);
  EXPECT_GT(r.out.internal_reflections, 0);
  EXPECT_NEAR(length(r.out.dir), 1, 1e-5);
  EXPECT_GT(r.out.weight, 0);
  EXPECT_LE(r.out.weight, 1);
}

// A cube of 12 triangles is a closed surface: the light leaves it where it leaves a cube primitive
// of the same size, through the same face, with the same normal and direction.
TEST(Glass, ACubeOfTrianglesLeavesWhereACubeDoes) {
  PrimitiveSet cube, mesh;
  cube.add_cube({0, 0, 0}, real(0.5));
  testing::add_box_triangles(mesh, {real(-0.5), real(-0.5), real(-0.5)}, {real(0.5), real(0.5), real(0.5)});
  Random rng(5);
  int crossed = 0;
  for (int k = 0; k < 200; ++k) {
    // From a point on a sphere around the cube towards a point inside it.
    const Vec3 o = real(3) * testing::random_direction(rng);
    const Vec3 d = normalize(testing::uniform_point(rng, -0.4, 0.4) - o);
    const real gap = real(0.005);
    const SlabResult a = cross_slab(cube, o, d, gap), b = cross_slab(mesh, o, d, gap);
    ASSERT_GE(a.out.last, 0);
    ASSERT_GE(b.out.last, 0) << "ray " << k;
    EXPECT_EQ(b.out.elements, a.out.elements);
    EXPECT_EQ(b.out.internal_reflections, a.out.internal_reflections);
    for (const auto& [x, y] : {std::pair{a.entry, b.entry}, std::pair{a.out.point, b.out.point},
                               std::pair{a.out.dir, b.out.dir}}) {
      EXPECT_NEAR(x.x, y.x, 1e-5) << "ray " << k;
      EXPECT_NEAR(x.y, y.y, 1e-5) << "ray " << k;
      EXPECT_NEAR(x.z, y.z, 1e-5) << "ray " << k;
    }
    EXPECT_NEAR(b.out.weight, a.out.weight, 1e-5);
    ++crossed;
  }
  EXPECT_EQ(crossed, 200);
}

// The exit of a closed triangle surface (union_walk.h): the nearest triangle beyond the entry,
// its normal along the ray, whatever elements lie about.
TEST(Glass, TheExitOfATriangleSurfaceIsItsNextCrossing) {
  PrimitiveSet mesh;
  testing::add_box_triangles(mesh, {-1, -1, -1}, {1, 1, 1});
  const KdTree tree = build_kdtree(mesh.bounds());
  const Ray r = make_ray({real(0.2), real(0.1), -1}, normalize(Vec3{0, real(0.3), 1}), real(1e-4), INFINITY);
  const UnionExit e = union_exit(tree.view(), mesh.view(), r, 8, real(0.01));
  ASSERT_GE(e.last, 0);
  const Vec3 x = r.o + e.t * r.d;
  EXPECT_NEAR(x.y, real(0.1) + real(0.6), 1e-5);  // through z = 1 after 2 along z
  EXPECT_NEAR(x.z, 1, 1e-5);
  EXPECT_NEAR(e.normal.z, 1, 1e-6);
  EXPECT_GT(dot(e.normal, r.d), 0);
}

}  // namespace
}  // namespace pd
