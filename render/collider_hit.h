// Rays against the colliders (cuda/views.h Collider), so the renderer draws the spheres, boxes,
// capsules and cylinders that push the particles, at their pose of the frame. Analytic, in each
// shape's frame (a mesh by sphere tracing its distance grid); a ray that starts inside a collider
// does not see it. Planes are not drawn (the renderer's floor stands for the ground).
#pragma once

#include <cmath>

#include "cuda/kernels/colliders.h"
#include "render/geometry.h"

namespace pd {

// The interval of t where o + t d lies inside the sphere of radius r at the origin.
PD_HD inline bool sphere_interval(Vec3 o, Vec3 d, real r, real* t0, real* t1) {
  const real a = dot(d, d), b = dot(o, d), c = dot(o, o) - r * r;
  const real disc = b * b - a * c;
  if (!(disc >= 0) || !(a > 0)) return false;
  const real s = std::sqrt(disc);
  *t0 = (-b - s) / a;
  *t1 = (-b + s) / a;
  return true;
}

// Inside the infinite cylinder of radius r about the y axis, between y = -h and h.
PD_HD inline bool cylinder_interval(Vec3 o, Vec3 d, real r, real h, real* t0, real* t1) {
  const real a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z - r * r;
  real lo = -INFINITY, hi = INFINITY;
  if (a > 0) {
    const real disc = b * b - a * c;
    if (!(disc >= 0)) return false;
    const real s = std::sqrt(disc);
    lo = (-b - s) / a;
    hi = (-b + s) / a;
  } else if (c > 0) {
    return false;  // parallel to the axis, outside
  }
  if (d.y != 0) {
    const real ya = (-h - o.y) / d.y, yb = (h - o.y) / d.y;
    lo = max_of(lo, min_of(ya, yb));
    hi = min_of(hi, max_of(ya, yb));
  } else if (std::abs(o.y) > h) {
    return false;
  }
  *t0 = lo;
  *t1 = hi;
  return lo <= hi;
}

// Sphere tracing through a mesh collider's distance grid: steps of the distance (at least a
// twentieth of a cell) from where the ray enters the grid, until within 0.3 cells of the surface
// (an open sheet's unsigned field never reaches 0 between nodes).
PD_HD inline bool grid_entry(const Collider& c, Vec3 o, Vec3 d, real tmin, real tmax, const float* grids,
                             real* t) {
  const Vec3 lo = c.grid_origin;
  const Vec3 hi =
      lo + c.grid_cell * Vec3{real(c.grid_dims[0] - 1), real(c.grid_dims[1] - 1), real(c.grid_dims[2] - 1)};
  real t0, t1;
  int entry_axis, exit_axis;
  if (!line_box_interval(make_ray(o, d, tmin, tmax), lo, hi, &t0, &t1, &entry_axis, &exit_axis)) return false;
  const real speed = length(d);
  real s = max_of(t0, tmin);
  t1 = min_of(t1, tmax);
  for (int step = 0; step < 1024 && s <= t1; ++step) {
    const real distance = grid_surface(c, o + s * d, grids).distance;
    if (distance < real(0.3) * c.grid_cell) {
      if (!(s > tmin)) return false;  // (starts at the surface or inside)
      *t = s;
      return true;
    }
    s += max_of(distance, real(0.05) * c.grid_cell) / speed;
  }
  return false;
}

// The entry t of o + t d (shape frame) into the shape, when it is in (tmin, tmax].
PD_HD inline bool shape_entry(const Collider& c, Vec3 o, Vec3 d, real tmin, real tmax, const float* grids,
                              real* t) {
  real best = INFINITY, t0, t1;
  auto take = [&](bool inside) {
    if (inside && t0 <= t1 && t0 > tmin && t0 < best) best = t0;
  };
  switch (c.shape) {
    case kColliderSphere:
      take(sphere_interval(o, d, c.size.x, &t0, &t1));
      break;
    case kColliderBox: {
      const Ray r = make_ray(o, d, tmin, tmax);
      int entry_axis, exit_axis;
      take(line_box_interval(r, real(-1) * c.size, c.size, &t0, &t1, &entry_axis, &exit_axis));
      break;
    }
    case kColliderCylinder:
      take(cylinder_interval(o, d, c.size.x, c.size.y, &t0, &t1));
      break;
    case kColliderCapsule:  // the union of its side and its two end balls: the first entry
      take(cylinder_interval(o, d, c.size.x, c.size.y, &t0, &t1));
      take(sphere_interval(o - Vec3{0, c.size.y, 0}, d, c.size.x, &t0, &t1));
      take(sphere_interval(o + Vec3{0, c.size.y, 0}, d, c.size.x, &t0, &t1));
      break;
    case kColliderMesh:
      if (!grids) return false;
      return grid_entry(c, o, d, tmin, tmax, grids, t);
    default:  // a plane: not drawn
      return false;
  }
  *t = best;
  return best <= tmax;
}

// The nearest collider the ray enters before `*t`: its index (and *t, *normal updated), or -1.
PD_HD inline int32_t nearest_collider(ArrayView<const Collider> colliders, const Ray& ray, real* t,
                                      Vec3* normal, const float* grids = nullptr) {
  int32_t found = -1;
  for (int64_t k = 0; k < colliders.size; ++k) {
    const Collider& c = colliders[k];
    const real* m = c.rotation;
    const Vec3 q = ray.o - c.center;  // R^T (o - centre), R^T d
    const Vec3 o{m[0] * q.x + m[3] * q.y + m[6] * q.z, m[1] * q.x + m[4] * q.y + m[7] * q.z,
                 m[2] * q.x + m[5] * q.y + m[8] * q.z};
    const Vec3 d{m[0] * ray.d.x + m[3] * ray.d.y + m[6] * ray.d.z,
                 m[1] * ray.d.x + m[4] * ray.d.y + m[7] * ray.d.z,
                 m[2] * ray.d.x + m[5] * ray.d.y + m[8] * ray.d.z};
    real entry;
    if (!shape_entry(c, o, d, ray.tmin, *t, grids, &entry) || !(entry < *t)) continue;
    *t = entry;
    *normal = collider_surface(c, ray.o + entry * ray.d, grids).normal;
    found = int32_t(k);
  }
  return found;
}

}  // namespace pd
