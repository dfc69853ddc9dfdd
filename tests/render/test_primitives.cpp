// Cube, oriented cube and tetrahedron intersection against analytic cases.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "host/geometry/random.h"
#include "render/primitive_set.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

Ray ray(Vec3 o, Vec3 d, real tmin = 0, real tmax = INFINITY) {
  return make_ray(o, normalize(d), tmin, tmax);
}

void expect_vec(Vec3 a, Vec3 b, real tol = real(1e-6)) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

const Vec3 kOrigin{0, 0, 0};

TEST(CubeIntersection, EntryFaceFromEachSide) {
  SurfaceHit h;
  ASSERT_TRUE(intersect_cube(ray({-5, real(0.2), real(0.3)}, {1, 0, 0}), kOrigin, 1, &h));
  EXPECT_EQ(h.t, 4);
  expect_vec(h.normal, {-1, 0, 0});
  ASSERT_TRUE(intersect_cube(ray({real(0.5), 5, real(-0.25)}, {0, -1, 0}), kOrigin, 1, &h));
  EXPECT_EQ(h.t, 4);
  expect_vec(h.normal, {0, 1, 0});
  ASSERT_TRUE(intersect_cube(ray({0, 0, 7}, {0, 0, -1}), {0, 0, 2}, real(0.5), &h));
  EXPECT_EQ(h.t, real(4.5));
  expect_vec(h.normal, {0, 0, 1});
}

TEST(CubeIntersection, ObliqueRayEntersThroughTheNearerFace) {
  // Slope 0.2 from (-3, 0.5, 0): reaches the face x = -1 at y = 0.9, inside it.
  const Vec3 d = normalize({1, real(0.2), 0});
  SurfaceHit h;
  ASSERT_TRUE(intersect_cube(make_ray({-3, real(0.5), 0}, d, 0, INFINITY), kOrigin, 1, &h));
  EXPECT_NEAR(h.t, 2 / d.x, 1e-5);
  expect_vec(h.normal, {-1, 0, 0});
  // Slope 0.6: already at y = 1.7 when x = -1, and y = 1 was crossed at x < -1: passes above.
  EXPECT_FALSE(intersect_cube(ray({-3, real(0.5), 0}, {1, real(0.6), 0}), kOrigin, 1, &h));
  // From above at 45 degrees onto the top face: enters at y = 1 where x = -0.5.
  ASSERT_TRUE(intersect_cube(ray({real(-1.5), 2, 0}, {1, -1, 0}), kOrigin, 1, &h));
  EXPECT_NEAR(h.t, std::sqrt(real(2)), 1e-5);
  expect_vec(h.normal, {0, 1, 0});
}

TEST(CubeIntersection, RayStartingInsideHitsTheExitFace) {
  SurfaceHit h;
  ASSERT_TRUE(intersect_cube(ray({real(0.25), 0, 0}, {1, 0, 0}), kOrigin, 1, &h));
  EXPECT_EQ(h.t, real(0.75));
  expect_vec(h.normal, {1, 0, 0});
  ASSERT_TRUE(intersect_cube(ray({0, real(-0.5), real(0.1)}, {0, -1, 0}), kOrigin, 1, &h));
  EXPECT_EQ(h.t, real(0.5));
  expect_vec(h.normal, {0, -1, 0});
}

TEST(CubeIntersection, MissesBehindBeyondTmaxAndBesides) {
  SurfaceHit h;
  EXPECT_FALSE(intersect_cube(ray({5, 0, 0}, {1, 0, 0}), kOrigin, 1, &h));         // behind
  EXPECT_FALSE(intersect_cube(ray({-5, 0, 0}, {1, 0, 0}, 0, 3), kOrigin, 1, &h));  // beyond tmax
  EXPECT_TRUE(intersect_cube(ray({-5, 0, 0}, {1, 0, 0}, 0, 4), kOrigin, 1, &h));   // tmax inclusive
  // tmin is exclusive: starting the interval at the entry point reports the exit.
  ASSERT_TRUE(intersect_cube(ray({-5, 0, 0}, {1, 0, 0}, 4, 10), kOrigin, 1, &h));
  EXPECT_EQ(h.t, 6);
  expect_vec(h.normal, {1, 0, 0});
  EXPECT_FALSE(intersect_cube(ray({-5, 2, 0}, {1, 0, 0}), kOrigin, 1, &h));  // passes beside
}

TEST(CubeIntersection, RaysInAFacePlaneFollowTheHalfOpenRule) {
  SurfaceHit h;
  // In the plane of the lower y face: inside the slab [lo, hi), hit.
  ASSERT_TRUE(intersect_cube(ray({-5, -1, 0}, {1, 0, 0}), kOrigin, 1, &h));
  EXPECT_EQ(h.t, 4);
  // In the plane of the upper y face: outside, miss.
  EXPECT_FALSE(intersect_cube(ray({-5, 1, 0}, {1, 0, 0}), kOrigin, 1, &h));
}

const Vec3 kTet[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

// The face planes intersect_tet takes.
std::array<TetPlane, 4> planes(const Vec3* v) {
  std::array<TetPlane, 4> p;
  tet_planes(v, p.data());
  return p;
}

TEST(TetIntersection, EntryThroughAnAxisFaceAndTheSlantedFace) {
  SurfaceHit h;
  ASSERT_TRUE(intersect_tet(ray({real(0.1), real(0.1), -1}, {0, 0, 1}), planes(kTet).data(), &h));
  EXPECT_NEAR(h.t, 1, 1e-6);
  expect_vec(h.normal, {0, 0, -1});
  // From (1,1,1) towards the origin: enters x + y + z = 1 at (1/3, 1/3, 1/3).
  ASSERT_TRUE(intersect_tet(ray({1, 1, 1}, {-1, -1, -1}), planes(kTet).data(), &h));
  EXPECT_NEAR(h.t, 2 / std::sqrt(real(3)), 1e-6);
  const real s = 1 / std::sqrt(real(3));
  expect_vec(h.normal, {s, s, s});
}

TEST(TetIntersection, RayStartingInsideHitsTheExitFace) {
  SurfaceHit h;
  ASSERT_TRUE(intersect_tet(ray({real(0.1), real(0.1), real(0.1)}, {0, 0, 1}), planes(kTet).data(), &h));
  EXPECT_NEAR(h.t, real(0.7), 1e-6);
  const real s = 1 / std::sqrt(real(3));
  expect_vec(h.normal, {s, s, s});
  ASSERT_TRUE(intersect_tet(ray({real(0.2), real(0.1), real(0.1)}, {-1, 0, 0}), planes(kTet).data(), &h));
  EXPECT_NEAR(h.t, real(0.2), 1e-6);
  expect_vec(h.normal, {-1, 0, 0});
}

TEST(TetIntersection, MissesAndVertexOrderDoesNotMatter) {
  SurfaceHit h;
  EXPECT_FALSE(intersect_tet(ray({2, 2, -1}, {0, 0, 1}), planes(kTet).data(), &h));
  EXPECT_FALSE(intersect_tet(ray({real(0.1), real(0.1), 2}, {0, 0, 1}), planes(kTet).data(), &h));  // behind
  // Mirrored orientation (two vertices swapped) gives the same hit.
  const Vec3 swapped[4] = {kTet[1], kTet[0], kTet[2], kTet[3]};
  SurfaceHit a, b;
  const Ray r = ray({real(0.3), real(-2), real(0.2)}, {real(0.05), 1, real(0.1)});
  ASSERT_TRUE(intersect_tet(r, planes(kTet).data(), &a));
  ASSERT_TRUE(intersect_tet(r, planes(swapped).data(), &b));
  EXPECT_EQ(a.t, b.t);
  expect_vec(a.normal, {0, -1, 0});
  expect_vec(b.normal, a.normal);
}

// A cube turned by 30 degrees about y: axes x' = (c, 0, -s), y' = y, z' = (s, 0, c).
const real kC = std::cos(real(0.5235987755982988)), kS = std::sin(real(0.5235987755982988));
const Vec3 kTurned[3] = {{kC, 0, -kS}, {0, 1, 0}, {kS, 0, kC}};

TEST(OrientedCubeIntersection, EntryFaceIsTheTurnedFace) {
  SurfaceHit h;
  // Along -x' from outside: enters through the +x' face at distance 5 - 1.
  const Vec3 c{1, 2, 3};
  ASSERT_TRUE(intersect_oriented_cube(ray(c + 5 * kTurned[0], -kTurned[0]), c, 1, kTurned, &h));
  EXPECT_NEAR(h.t, 4, 1e-5);
  expect_vec(h.normal, kTurned[0]);
  // Down the y axis: the top face, normal +y.
  ASSERT_TRUE(intersect_oriented_cube(ray(c + Vec3{real(0.2), 4, 0}, {0, -1, 0}), c, 1, kTurned, &h));
  EXPECT_NEAR(h.t, 3, 1e-5);
  expect_vec(h.normal, {0, 1, 0});
  // Along world x through the centre: the slanted face -x' at distance 1 / cos 30 from the centre.
  ASSERT_TRUE(intersect_oriented_cube(ray(c - Vec3{5, 0, 0}, {1, 0, 0}), c, 1, kTurned, &h));
  EXPECT_NEAR(h.t, 5 - 1 / kC, 1e-5);
  expect_vec(h.normal, -kTurned[0]);
}

TEST(OrientedCubeIntersection, InsideExitContainmentAndBounds) {
  SurfaceHit h;
  PrimitiveSet s;
  s.add_oriented_cube({0, 0, 0}, 1, kTurned);
  const PrimitivesView v = s.view();
  // From the centre along z': the exit face +z' at t = 1, for intersect and primitive_exit alike.
  ASSERT_TRUE(intersect_primitive(v, 0, ray(kOrigin, kTurned[2]), &h));
  EXPECT_NEAR(h.t, 1, 1e-6);
  expect_vec(h.normal, kTurned[2]);
  ASSERT_TRUE(primitive_exit(v, 0, ray(kOrigin, kTurned[2]), &h));
  EXPECT_NEAR(h.t, 1, 1e-6);
  expect_vec(h.normal, kTurned[2]);
  // (1.1, 0, 0) lies outside the axis-aligned unit cube but inside the turned one (|x'| = 0.95);
  // (0.9, 0, 0.9) inside the axis-aligned one, outside the turned one (z' = 1.23).
  EXPECT_TRUE(primitive_contains(v, 0, {real(1.1), 0, 0}));
  EXPECT_FALSE(primitive_contains(v, 0, {real(0.9), 0, real(0.9)}));
  // Bounds: the turned cube reaches cos 30 + sin 30 along x and z, 1 along y.
  const Box b = primitive_bounds(v, 0);
  EXPECT_NEAR(b.hi.x, kC + kS, 1e-5);
  EXPECT_NEAR(b.lo.z, -(kC + kS), 1e-5);
  EXPECT_NEAR(b.hi.y, 1, 1e-5);
  EXPECT_GE(b.hi.x, kC + kS);  // never narrower than the exact extent
}

// Random rays: a reported hit lies on the surface, and the normal's face is the one crossed.
TEST(PrimitiveIntersection, RandomHitsLieOnTheSurface) {
  Random rng(3);
  auto u = [&](double a, double b) { return real(a + (b - a) * rng.uniform()); };
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Ray r = ray({u(-3, 3), u(-3, 3), u(-3, 3)}, {u(-1, 1), u(-1, 1), u(-1, 1)});
    SurfaceHit h;
    if (intersect_cube(r, {real(0.1), real(-0.2), real(0.3)}, real(0.8), &h)) {
      ++hits;
      const Vec3 p = r.o + h.t * r.d - Vec3{real(0.1), real(-0.2), real(0.3)};
      const real linf = rmax(std::fabs(p.x), rmax(std::fabs(p.y), std::fabs(p.z)));
      EXPECT_NEAR(linf, real(0.8), 1e-5);
      EXPECT_NEAR(dot(p, h.normal), real(0.8), 1e-5);  // on the face the normal names
    }
    if (intersect_oriented_cube(r, {real(0.1), real(-0.2), real(0.3)}, real(0.8), kTurned, &h)) {
      ++hits;
      const Vec3 p = r.o + h.t * r.d - Vec3{real(0.1), real(-0.2), real(0.3)};
      const Vec3 q{dot(p, kTurned[0]), dot(p, kTurned[1]), dot(p, kTurned[2])};
      EXPECT_NEAR(rmax(std::fabs(q.x), rmax(std::fabs(q.y), std::fabs(q.z))), real(0.8), 1e-5);
      EXPECT_NEAR(dot(p, h.normal), real(0.8), 1e-5);
    }
    if (intersect_tet(r, planes(kTet).data(), &h)) {
      ++hits;
      const Vec3 p = r.o + h.t * r.d;
      // On the plane of the face named by the normal, inside the tet's closure.
      const real offset = h.normal.x + h.normal.y + h.normal.z > real(0.5) ? 1 / std::sqrt(real(3)) : 0;
      EXPECT_NEAR(dot(p, h.normal), offset, 1e-5);
      EXPECT_GE(rmin(p.x, rmin(p.y, p.z)), -1e-5);
      EXPECT_LE(p.x + p.y + p.z, 1 + 1e-5);
    }
  }
  EXPECT_GT(hits, 150);
}

// The triangle (0,0,0), (1,0,0), (0,1,0): counter-clockwise seen from +z, so +z is outside.
const Vec3 kTri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
const Vec3 kUp[3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};

TEST(TriangleIntersection, HitFromEitherSideWithTheOutwardNormal) {
  SurfaceHit h;
  ASSERT_TRUE(intersect_triangle(ray({real(0.25), real(0.25), 2}, {0, 0, -1}), kTri, kUp, &h));
  EXPECT_EQ(h.t, 2);
  expect_vec(h.normal, {0, 0, 1});  // against the ray: an entry
  ASSERT_TRUE(intersect_triangle(ray({real(0.25), real(0.25), -3}, {0, 0, 1}), kTri, kUp, &h));
  EXPECT_EQ(h.t, 3);
  expect_vec(h.normal, {0, 0, 1});  // along the ray: an exit, still outward
  // Oblique: t is the distance along the unit direction.
  const Vec3 d = normalize({real(0.1), real(0.2), -1});
  ASSERT_TRUE(intersect_triangle(make_ray(Vec3{real(0.2), real(0.1), 1}, d, 0, INFINITY), kTri, kUp, &h));
  EXPECT_NEAR(h.t, 1 / -d.z, 1e-6);
  // The geometric normal of the winding.
  expect_vec(triangle_normal(kTri), {0, 0, 1});
  const Vec3 flipped[3] = {kTri[0], kTri[2], kTri[1]};
  expect_vec(triangle_normal(flipped), {0, 0, -1});
}

TEST(TriangleIntersection, MissesOutsideBehindBeyondTmaxAndParallel) {
  SurfaceHit h;
  EXPECT_FALSE(
      intersect_triangle(ray({real(0.6), real(0.6), 1}, {0, 0, -1}), kTri, kUp, &h));  // past the hypotenuse
  EXPECT_FALSE(intersect_triangle(ray({real(-0.1), real(0.5), 1}, {0, 0, -1}), kTri, kUp, &h));
  EXPECT_FALSE(intersect_triangle(ray({real(0.2), real(0.2), 1}, {0, 0, 1}), kTri, kUp, &h));  // behind
  EXPECT_FALSE(intersect_triangle(ray({real(0.2), real(0.2), 1}, {0, 0, -1}, 0, real(0.5)), kTri, kUp, &h));
  EXPECT_FALSE(intersect_triangle(ray({real(0.2), real(0.2), 1}, {0, 0, -1}, real(1.5)), kTri, kUp, &h));
  EXPECT_FALSE(intersect_triangle(ray({-1, real(0.2), 0}, {1, 0, 0}), kTri, kUp, &h));  // in its plane
}

// Watertight: a square of 2 x 2 cells cut into 8 triangles. Rays aimed at the shared edges and
// vertices, straight and oblique, hit at least one triangle, and a ray never hits two triangles at
// different t.
TEST(TriangleIntersection, RaysThroughSharedEdgesAndVerticesAreNotLost) {
  PrimitiveSet grid;
  const real s = real(0.1);
  auto p = [&](int i, int j) { return Vec3{i * s, j * s, real(0.3)}; };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      grid.add_triangle(p(i, j), p(i + 1, j), p(i + 1, j + 1));
      grid.add_triangle(p(i, j), p(i + 1, j + 1), p(i, j + 1));
    }
  const PrimitivesView v = grid.view();
  Random rng(3);
  int rays = 0;
  for (int k = 0; k < 400; ++k) {
    // A point on an interior edge (x = s, y = s, or a cell's diagonal), or the centre vertex.
    const real u = real(rng.uniform()) * s;
    const int cell = k % 4;
    const Vec3 targets[4] = {{s, 2 * u, real(0.3)},
                             {2 * u, s, real(0.3)},
                             {(cell % 2) * s + u, (cell / 2) * s + u, real(0.3)},
                             p(1, 1)};
    const Vec3 target = targets[(k / 2) % 4];
    const Vec3 d = k % 2 ? Vec3{0, 0, -1} : testing::random_direction(rng);
    if (std::fabs(d.z) < real(0.2)) continue;
    const Vec3 o = target - real(2) * d;
    const Ray r = make_ray(o, d, 0, INFINITY);
    int hits = 0;
    real first_t = 0;
    for (int32_t i = 0; i < v.n; ++i) {
      SurfaceHit h;
      if (!intersect_primitive(v, i, r, &h)) continue;
      if (hits++ == 0) first_t = h.t;
      EXPECT_NEAR(h.t, first_t, 1e-6);
    }
    EXPECT_GE(hits, 1) << "ray " << k << " through (" << target.x << ", " << target.y << ")";
    ++rays;
  }
  EXPECT_GT(rays, 300);
}

TEST(TriangleIntersection, ShadingNormalInterpolatesTheVertexNormals) {
  const Vec3 n[3] = {normalize({-1, 0, 1}), normalize({1, 0, 1}), {0, 0, 1}};
  SurfaceHit h;
  // At vertex 0 the normal is vertex 0's, halfway between vertices 0 and 1 their mean.
  ASSERT_TRUE(intersect_triangle(ray({real(1e-4), real(1e-4), 1}, {0, 0, -1}), kTri, n, &h));
  expect_vec(h.normal, n[0], real(1e-3));
  ASSERT_TRUE(intersect_triangle(ray({real(0.5), 0, 1}, {0, 0, -1}), kTri, n, &h));
  expect_vec(h.normal, {0, 0, 1});
  // At barycentric (0.25, 0.25, 0.5): normalize(0.25 n0 + 0.25 n1 + 0.5 n2).
  ASSERT_TRUE(intersect_triangle(ray({real(0.25), real(0.5), 1}, {0, 0, -1}), kTri, n, &h));
  expect_vec(h.normal, normalize(real(0.25) * n[0] + real(0.25) * n[1] + real(0.5) * n[2]));
}

TEST(TriangleIntersection, NormalStaysOnTheGeometricSide) {
  SurfaceHit h;
  // Vertex normals pointing into the material: mirrored through the plane, to the outside.
  const Vec3 inward[3] = {normalize({real(0.3), 0, -1}), normalize({real(0.3), 0, -1}),
                          normalize({real(0.3), 0, -1})};
  ASSERT_TRUE(intersect_triangle(ray({real(0.2), real(0.2), 1}, {0, 0, -1}), kTri, inward, &h));
  expect_vec(h.normal, normalize({real(0.3), 0, 1}));
  // A grazing ray that enters the triangle's front side while the smooth normal faces away from
  // it: the geometric normal, so that the hit still reads as an entry (dot(normal, d) < 0).
  const Vec3 tilted[3] = {normalize({1, 0, real(0.2)}), normalize({1, 0, real(0.2)}),
                          normalize({1, 0, real(0.2)})};
  const Vec3 d = normalize({1, 0, real(-0.1)});
  ASSERT_TRUE(intersect_triangle(make_ray(Vec3{real(0.1), real(0.2), 0} - real(1) * d, d, 0, INFINITY), kTri,
                                 tilted, &h));
  EXPECT_LT(dot(h.normal, d), 0);
  expect_vec(h.normal, {0, 0, 1});
}

TEST(TriangleIntersection, PrimitiveDispatchBoundsAndNoSolid) {
  PrimitiveSet p;
  p.add_cube({5, 5, 5}, 1);
  const int32_t t = p.add_triangle(kTri[0], kTri[1], kTri[2]);
  const PrimitivesView v = p.view();
  EXPECT_EQ(v.kind[t], kPrimTriangle);
  SurfaceHit h;
  ASSERT_TRUE(intersect_primitive(v, t, ray({real(0.2), real(0.2), -1}, {0, 0, 1}), &h));
  EXPECT_EQ(h.t, 1);
  expect_vec(h.normal, {0, 0, 1});
  const Box b = primitive_bounds(v, t);
  EXPECT_LE(b.lo.x, 0);
  EXPECT_GE(b.hi.y, 1);
  EXPECT_LT(b.lo.z, 0);  // widened: a flat box would lose round-off hits
  EXPECT_GT(b.hi.z, 0);
  EXPECT_LT(b.hi.z - b.lo.z, 1e-5);
  EXPECT_FALSE(primitive_contains(v, t, {real(0.2), real(0.2), 0}));
  EXPECT_FALSE(primitive_exit(v, t, ray({real(0.2), real(0.2), -1}, {0, 0, 1}), &h));
}

}  // namespace
}  // namespace pd
