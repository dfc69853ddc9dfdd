// Test scenes and the brute-force nearest-hit oracle shared by the render suites.
#pragma once

#include <vector>

#include "host/random.h"
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

// An nx x ny x nz block of face-adjacent cubes of side `spacing`.
inline PrimitiveSet lattice_scene(int nx, int ny, int nz, real spacing) {
  PrimitiveSet s;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) s.add_cube({i * spacing, j * spacing, k * spacing}, spacing / 2);
  return s;
}

}  // namespace pd::testing
