// Ray-tracing geometry shared by host and device: vector helpers Vec3 lacks, rays and
// axis-aligned boxes. All functions are PD_HD so the kd-tree, the intersection tests and the
// renderer kernel compile for both backends.
#pragma once

#include <cmath>

#include "cuda/array_view.h"
#include "cuda/vec3.h"

namespace pd {

PD_HD inline real rmin(real a, real b) {
  return a < b ? a : b;
}
PD_HD inline real rmax(real a, real b) {
  return a > b ? a : b;
}
PD_HD inline real clamp01(real a) {
  return a < 0 ? real(0) : (a > 1 ? real(1) : a);
}

PD_HD inline Vec3 normalize(Vec3 a) {
  return (real(1) / length(a)) * a;
}
// Component-wise product (colours).
PD_HD inline Vec3 mul(Vec3 a, Vec3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
PD_HD inline Vec3 lerp(Vec3 a, Vec3 b, real s) {
  return a + s * (b - a);
}
PD_HD inline real axis_of(Vec3 v, int axis) {
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}
PD_HD inline Vec3 vmin(Vec3 a, Vec3 b) {
  return {rmin(a.x, b.x), rmin(a.y, b.y), rmin(a.z, b.z)};
}
PD_HD inline Vec3 vmax(Vec3 a, Vec3 b) {
  return {rmax(a.x, b.x), rmax(a.y, b.y), rmax(a.z, b.z)};
}

// A ray o + t d restricted to t in (tmin, tmax]. inv_d holds 1/d per axis; make_ray flushes
// direction components too small to invert to exactly zero, so every test treats such an axis
// as parallel instead of dividing by a denormal.
struct Ray {
  Vec3 o, d, inv_d;
  real tmin, tmax;
};

PD_HD inline real flush_tiny(real v) {
  return std::fabs(v) < real(1e-30) ? real(0) : v;
}

PD_HD inline Ray make_ray(Vec3 o, Vec3 d, real tmin, real tmax) {
  Ray r;
  r.o = o;
  r.d = {flush_tiny(d.x), flush_tiny(d.y), flush_tiny(d.z)};
  r.inv_d = {real(1) / r.d.x, real(1) / r.d.y, real(1) / r.d.z};
  r.tmin = tmin;
  r.tmax = tmax;
  return r;
}

// A ray's crossing of a primitive's surface.
struct SurfaceHit {
  real t;
  Vec3 normal;  // outward unit normal of the face crossed
};

// Axis-aligned box [lo, hi].
struct Box {
  Vec3 lo, hi;
};

// One slab of a box test: narrows [t0, t1] to where the ray is inside lo <= x < hi along
// `axis`; remembers which axis set t0 (entry) and t1 (exit). A ray parallel to the slab is
// inside it iff lo <= o < hi: the half-open rule the kd-tree traversal uses for rays lying in
// a split plane (they belong to the side above the plane). Returns false on a miss.
PD_HD inline bool clip_slab(const Ray& r, int axis, real lo, real hi, real* t0, real* t1, int* entry_axis,
                            int* exit_axis) {
  const real o = axis_of(r.o, axis), d = axis_of(r.d, axis);
  if (d == 0) return lo <= o && o < hi;
  const real inv = axis_of(r.inv_d, axis);
  const real tn = ((d > 0 ? lo : hi) - o) * inv;
  const real tf = ((d > 0 ? hi : lo) - o) * inv;
  if (tn > *t0) {
    *t0 = tn;
    *entry_axis = axis;
  }
  if (tf < *t1) {
    *t1 = tf;
    *exit_axis = axis;
  }
  return true;
}

// The parameter interval [t0, t1] in which the ray's line is inside the box (slab test;
// unbounded lines give infinities). Returns false when the line misses the box.
PD_HD inline bool line_box_interval(const Ray& r, Vec3 lo, Vec3 hi, real* t0, real* t1, int* entry_axis,
                                    int* exit_axis) {
  *t0 = -INFINITY;
  *t1 = INFINITY;
  *entry_axis = *exit_axis = -1;
  if (!clip_slab(r, 0, lo.x, hi.x, t0, t1, entry_axis, exit_axis)) return false;
  if (!clip_slab(r, 1, lo.y, hi.y, t0, t1, entry_axis, exit_axis)) return false;
  if (!clip_slab(r, 2, lo.z, hi.z, t0, t1, entry_axis, exit_axis)) return false;
  return *t0 <= *t1;
}

}  // namespace pd
