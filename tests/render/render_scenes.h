// Test scenes and the brute-force nearest-hit oracle shared by the render suites.
#pragma once

#include <cmath>
#include <vector>

#include "host/geometry/random.h"
#include "render/primitive_set.h"
#include "render/traverse.h"

namespace pd::testing {

// Nearest hit over all primitives, ties to the smallest id: what the kd-tree must reproduce.
inline Hit brute_force_hit(const PrimitivesView& p, const Ray& ray) {
  Hit best;
  for (int32_t i = 0; i < p.n; ++i) {
    Ray r = ray;
    if (best.prim >= 0) r.tmax = best.t;
    SurfaceHit h;
    if (intersect_primitive(p, i, r, &h) && (best.prim < 0 || h.t < best.t)) best = {i, h.t, h.normal};
  }
  return best;
}

inline real uniform(Random& rng, double a, double b) {
  return real(a + (b - a) * rng.uniform());
}

inline Vec3 uniform_point(Random& rng, double a, double b) {
  return {uniform(rng, a, b), uniform(rng, a, b), uniform(rng, a, b)};
}

// A unit vector, uniform on the sphere.
inline Vec3 random_direction(Random& rng) {
  for (;;) {
    const Vec3 v = uniform_point(rng, -1, 1);
    const real l = length(v);
    if (l > real(0.1) && l <= 1) return (1 / l) * v;
  }
}

// The columns of a uniformly random rotation (from a random unit quaternion): orthonormal axes.
inline void random_axes(Random& rng, Vec3 axis[3]) {
  double q[4], n = 0;
  do {
    n = 0;
    for (double& c : q) {
      c = 2 * rng.uniform() - 1;
      n += c * c;
    }
  } while (n > 1 || n < 0.01);
  const double w = q[0] / std::sqrt(n), x = q[1] / std::sqrt(n), y = q[2] / std::sqrt(n),
               z = q[3] / std::sqrt(n);
  axis[0] = {real(1 - 2 * (y * y + z * z)), real(2 * (x * y + w * z)), real(2 * (x * z - w * y))};
  axis[1] = {real(2 * (x * y - w * z)), real(1 - 2 * (x * x + z * z)), real(2 * (y * z + w * x))};
  axis[2] = {real(2 * (x * z + w * y)), real(2 * (y * z - w * x)), real(1 - 2 * (x * x + y * y))};
}

// The box [lo, hi] as 12 flat triangles, counter-clockwise seen from outside (a closed surface).
inline void add_box_triangles(PrimitiveSet& s, Vec3 lo, Vec3 hi) {
  const Vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z},
                     {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}};
  // Each face's corners counter-clockwise seen from outside (corner index bits: x, y, z).
  const int face[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : face) {
    s.add_triangle(c[f[0]], c[f[1]], c[f[2]]);
    s.add_triangle(c[f[0]], c[f[2]], c[f[3]]);
  }
}

// Triangles of assorted sizes and orientations in [-1, 1]^3, with random unit vertex normals on
// the side of their geometric normal.
inline void add_random_triangles(PrimitiveSet& s, Random& rng, int count) {
  for (int k = 0; k < count; ++k) {
    const Vec3 a = uniform_point(rng, -1, 1);
    const real size = uniform(rng, 0.01, 0.3);
    const Vec3 b = a + size * random_direction(rng), c = a + size * random_direction(rng);
    const Vec3 v[3] = {a, b, c};
    const Vec3 n = triangle_normal(v);
    Vec3 corner[3];
    for (Vec3& m : corner) m = normalize(n + real(0.5) * random_direction(rng));
    s.add_triangle(a, b, c, corner[0], corner[1], corner[2]);
  }
}

// Randomly turned cubes of assorted sizes in [-1, 1]^3.
inline void add_random_oriented_cubes(PrimitiveSet& s, Random& rng, int count) {
  for (int i = 0; i < count; ++i) {
    Vec3 axis[3];
    random_axes(rng, axis);
    s.add_oriented_cube(uniform_point(rng, -1, 1), uniform(rng, 0.01, 0.15), axis);
  }
}

// Overlapping cubes and tetrahedra of assorted sizes in [-1, 1]^3.
inline PrimitiveSet random_scene(uint64_t seed, int cubes, int tets) {
  Random rng(seed);
  PrimitiveSet s;
  for (int i = 0; i < cubes; ++i) s.add_cube(uniform_point(rng, -1, 1), uniform(rng, 0.01, 0.15));
  for (int i = 0; i < tets; ++i) {
    const Vec3 c = uniform_point(rng, -1, 1);
    const double r = 0.02 + 0.2 * rng.uniform();
    s.add_tet(c + uniform_point(rng, -r, r), c + uniform_point(rng, -r, r), c + uniform_point(rng, -r, r),
              c + uniform_point(rng, -r, r));
  }
  return s;
}

// A trimtope around centre c: the cube of half side h cut by three random planes that keep c,
// site V = c, and (unless `solid`) a surface of two large triangles on a random plane passing
// between V and the cube's corners, facing away from V, sometimes folded into a crease by a
// second pair. The cube is a valid bound of the solid part.
inline int32_t add_random_trimtope(PrimitiveSet& s, Random& rng, Vec3 c, real h, bool solid) {
  Vec3 normal[9];
  real offset[9];
  for (int a = 0; a < 3; ++a) {
    const Vec3 e{a == 0 ? real(1) : real(0), a == 1 ? real(1) : real(0), a == 2 ? real(1) : real(0)};
    normal[2 * a] = e;
    offset[2 * a] = dot(e, c) + h;
    normal[2 * a + 1] = -e;
    offset[2 * a + 1] = -dot(e, c) + h;
  }
  for (int k = 6; k < 9; ++k) {
    normal[k] = random_direction(rng);
    offset[k] = dot(normal[k], c) + uniform(rng, 0.3, 1.5) * h;
  }
  std::vector<Vec3> tri;
  const int sheets = solid ? 0 : (rng.uniform() < 0.3 ? 2 : 1);
  for (int k = 0; k < sheets; ++k) {
    // The plane dot(m, x - c) = q, q > 0, outward normal m; a square of side 8h on it.
    const Vec3 m = random_direction(rng);
    const real q = uniform(rng, 0.1, 0.8) * h;
    const Vec3 u = normalize(cross(m, std::fabs(m.x) < real(0.9) ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const Vec3 w = cross(m, u);  // (u, w, m) right-handed: u x w = m, so (a, b, c) below face +m
    const Vec3 o = c + q * m;
    const real e = 4 * h;
    const Vec3 p00 = o - e * u - e * w, p10 = o + e * u - e * w, p11 = o + e * u + e * w,
               p01 = o - e * u + e * w;
    tri.insert(tri.end(), {p00, p10, p11, p00, p11, p01});
  }
  const Box box{{c.x - h, c.y - h, c.z - h}, {c.x + h, c.y + h, c.z + h}};
  return s.add_trimtope(c, normal, offset, 9, tri.data(), int32_t(tri.size() / 3), box);
}

// Random trimtopes (a fifth of them without surface) mixed with cubes and tetrahedra.
inline PrimitiveSet random_trimtope_scene(uint64_t seed, int trimtopes, int cubes, int tets) {
  Random rng(seed);
  PrimitiveSet s = random_scene(seed + 1000, cubes, tets);
  for (int i = 0; i < trimtopes; ++i)
    add_random_trimtope(s, rng, uniform_point(rng, -1, 1), uniform(rng, 0.03, 0.15), rng.uniform() < 0.2);
  return s;
}

// An nx x ny x nz block of face-adjacent cubes of side `spacing` turned as one piece by `axis`
// about the origin (the faces of neighbours coincide up to round-off).
inline PrimitiveSet oriented_lattice_scene(int nx, int ny, int nz, real spacing, const Vec3 axis[3]) {
  PrimitiveSet s;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        s.add_oriented_cube((i * spacing) * axis[0] + (j * spacing) * axis[1] + (k * spacing) * axis[2],
                            spacing / 2, axis);
  return s;
}

// An nx x ny x nz block of face-adjacent cubes of side `spacing`.
inline PrimitiveSet lattice_scene(int nx, int ny, int nz, real spacing) {
  PrimitiveSet s;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) s.add_cube({i * spacing, j * spacing, k * spacing}, spacing / 2);
  return s;
}

}  // namespace pd::testing
