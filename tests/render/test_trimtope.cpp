// Trimtopes (render/trimtope.h): the rays A-D of Levine et al. 2014, Fig. 4, classified as the
// paper says, rays starting inside, exits and containment.
#include <gtest/gtest.h>

#include <vector>

#include "render/primitive_set.h"

namespace pd {
namespace {

// Fig. 4's set-up: the cell is the cube [-1, 1]^3, the site V = (0, -0.5, 0) lies below the
// surface mesh, a horizontal square at y = 0.5 facing up (+y, away from V). Optionally a small
// closed void (a box of inward-facing triangles) inside the solid between x = -0.55 and -0.45.
PrimitiveSet fig4_trimtope(bool with_void) {
  std::vector<Vec3> normal;
  std::vector<real> offset;
  for (int a = 0; a < 3; ++a)
    for (real s : {real(1), real(-1)}) {
      normal.push_back({a == 0 ? s : real(0), a == 1 ? s : real(0), a == 2 ? s : real(0)});
      offset.push_back(1);
    }
  // Square at y = 0.5 larger than the cell, counter-clockwise seen from above.
  const real y = real(0.5);
  std::vector<Vec3> tri = {{-2, y, 2}, {2, y, 2}, {2, y, -2}, {-2, y, 2}, {2, y, -2}, {-2, y, -2}};
  if (with_void) {
    // Box [-0.55, -0.45] x [-0.4, -0.3] x [-0.05, 0.05] as a void: its triangles face into it
    // (away from the material), i.e. inward for the box.
    const Vec3 lo{real(-0.55), real(-0.4), real(-0.05)}, hi{real(-0.45), real(-0.3), real(0.05)};
    auto corner = [&](int k) { return Vec3{k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z}; };
    // Outward-oriented quads of the box (corner indices), then reversed for the void.
    const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
      tri.insert(tri.end(), {corner(q[0]), corner(q[2]), corner(q[1])});
      tri.insert(tri.end(), {corner(q[0]), corner(q[3]), corner(q[2])});
    }
  }
  PrimitiveSet s;
  s.add_trimtope({0, real(-0.5), 0}, normal.data(), offset.data(), int32_t(normal.size()), tri.data(),
                 int32_t(tri.size() / 3), Box{{-1, -1, -1}, {1, real(0.5), 1}});
  return s;
}

struct Classified {
  bool hit;
  SurfaceHit h;
  TrimtopeCase which;
};

Classified classify(const PrimitiveSet& s, Vec3 o, Vec3 d, real tmin = 0) {
  Classified c{};
  c.hit = intersect_trimtope(s.view().trim, 0, make_ray(o, normalize(d), tmin, INFINITY), &c.h, &c.which);
  return c;
}

void expect_vec(Vec3 a, Vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-6);
  EXPECT_NEAR(a.y, b.y, 1e-6);
  EXPECT_NEAR(a.z, b.z, 1e-6);
}

TEST(Trimtope, RayAEntersAboveTheMeshAndMisses) {
  // Enters at P = (-1, 0.8, 0) and leaves without meeting the mesh; P -> V meets the mesh's
  // forward-facing side first.
  const Classified c = classify(fig4_trimtope(false), {-3, real(0.8), 0}, {1, 0, 0});
  EXPECT_EQ(c.which, kTrimA);
  EXPECT_FALSE(c.hit);
}

TEST(Trimtope, RayBEntersBelowTheMeshAndHitsAtTheEntryPoint) {
  // P -> V meets no triangle: the entry point on the cell face x = -1 is the hit.
  const Classified c = classify(fig4_trimtope(false), {-3, 0, 0}, {1, 0, 0});
  EXPECT_EQ(c.which, kTrimB);
  ASSERT_TRUE(c.hit);
  EXPECT_NEAR(c.h.t, 2, 1e-6);
  expect_vec(c.h.normal, {-1, 0, 0});
}

TEST(Trimtope, RayBWhoseSecondaryRayMeetsABackwardFacingTriangle) {
  // The ray at y = -0.2 passes above the void; P = (-1, -0.2, 0) -> V = (0, -0.5, 0) passes
  // through it and meets its backward-facing side first: P is inside, the entry is the hit.
  const PrimitiveSet s = fig4_trimtope(true);
  const Classified c = classify(s, {-3, real(-0.2), 0}, {1, 0, 0});
  EXPECT_EQ(c.which, kTrimB);
  ASSERT_TRUE(c.hit);
  EXPECT_NEAR(c.h.t, 2, 1e-6);
  // The secondary ray really crosses a triangle of the void, facing away from the segment's start.
  real t;
  Vec3 n;
  const Vec3 p{-1, real(-0.2), 0}, to_v = Vec3{0, real(-0.5), 0} - p;
  ASSERT_TRUE(first_triangle(s.view().trim, 0, p, to_v, 0, 1, &t, &n));
  EXPECT_GT(dot(n, to_v), 0);
}

TEST(Trimtope, RayCHitsTheForwardFacingMesh) {
  const Classified c = classify(fig4_trimtope(false), {0, 3, 0}, {0, -1, 0});
  EXPECT_EQ(c.which, kTrimC);
  ASSERT_TRUE(c.hit);
  EXPECT_NEAR(c.h.t, 2.5, 1e-6);
  expect_vec(c.h.normal, {0, 1, 0});
}

TEST(Trimtope, RayDMeetsTheBackwardFacingMeshAndHitsAtTheEntryPoint) {
  const Classified c = classify(fig4_trimtope(false), {0, -3, 0}, {0, 1, 0});
  EXPECT_EQ(c.which, kTrimD);
  ASSERT_TRUE(c.hit);
  EXPECT_NEAR(c.h.t, 2, 1e-6);
  expect_vec(c.h.normal, {0, -1, 0});
}

TEST(Trimtope, ObliqueRaysFollowTheSameRules) {
  const PrimitiveSet s = fig4_trimtope(false);
  // Enters through x = -1 below the mesh and rises through it: D (the entry point is the hit).
  const Classified d = classify(s, {-2, real(-0.5), 0}, {1, real(0.5), 0});
  EXPECT_EQ(d.which, kTrimD);
  EXPECT_NEAR(d.h.t * normalize({1, real(0.5), 0}).x, 1, 1e-5);
  // Enters through x = -1 above the mesh and falls through it: C, the hit on the mesh.
  const Classified c = classify(s, {-2, real(1.2), 0}, {1, real(-0.5), 0});
  EXPECT_EQ(c.which, kTrimC);
  EXPECT_NEAR(-2 + c.h.t * normalize({1, real(-0.5), 0}).x, -0.6, 1e-5);  // y = 1.2 - 0.5 (x + 2) = 0.5
}

TEST(Trimtope, RaysStartingInsideTheCell) {
  const PrimitiveSet s = fig4_trimtope(false);
  // Inside the object: leaves through the mesh, or through the cell face.
  Classified c = classify(s, {0, 0, 0}, {0, 1, 0});
  EXPECT_EQ(c.which, kTrimInsideTriangle);
  EXPECT_NEAR(c.h.t, 0.5, 1e-6);
  expect_vec(c.h.normal, {0, 1, 0});
  c = classify(s, {0, 0, 0}, {1, 0, 0});
  EXPECT_EQ(c.which, kTrimInsideExit);
  EXPECT_NEAR(c.h.t, 1, 1e-6);
  expect_vec(c.h.normal, {1, 0, 0});
  // Above the mesh: enters through it, or misses.
  c = classify(s, {0, real(0.8), 0}, {0, -1, 0});
  EXPECT_EQ(c.which, kTrimInsideTriangle);
  EXPECT_NEAR(c.h.t, 0.3, 1e-6);
  c = classify(s, {0, real(0.8), 0}, {1, 0, 0});
  EXPECT_EQ(c.which, kTrimInsideMiss);
  EXPECT_FALSE(c.hit);
  // A ray whose start (tmin) lies past the cell sees nothing.
  c = classify(s, {-3, 0, 0}, {1, 0, 0}, 5);
  EXPECT_EQ(c.which, kTrimNone);
}

TEST(Trimtope, ExitAndContainment) {
  const PrimitiveSet s = fig4_trimtope(true);
  const PrimitivesView v = s.view();
  EXPECT_TRUE(primitive_contains(v, 0, {0, 0, 0}));
  EXPECT_FALSE(primitive_contains(v, 0, {0, real(0.7), 0}));             // above the mesh
  EXPECT_FALSE(primitive_contains(v, 0, {real(-0.5), real(-0.35), 0}));  // in the void
  EXPECT_FALSE(primitive_contains(v, 0, {0, 0, real(1.5)}));             // outside the cell
  SurfaceHit h;
  ASSERT_TRUE(primitive_exit(v, 0, make_ray({0, -1, 0}, {0, 1, 0}, real(1e-4), INFINITY), &h));
  EXPECT_NEAR(h.t, 1.5, 1e-6);
  expect_vec(h.normal, {0, 1, 0});
  ASSERT_TRUE(primitive_exit(v, 0, make_ray({0, 0, 0}, {0, 0, -1}, 0, INFINITY), &h));
  EXPECT_NEAR(h.t, 1, 1e-6);
  expect_vec(h.normal, {0, 0, -1});
}

TEST(Trimtope, BoundsComeFromTheStoredBox) {
  const PrimitiveSet s = fig4_trimtope(false);
  const Box b = primitive_bounds(s.view(), 0);
  EXPECT_EQ(b.hi.y, real(0.5));
  EXPECT_EQ(b.lo.x, -1);
}

}  // namespace
}  // namespace pd
