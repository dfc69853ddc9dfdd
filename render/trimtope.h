// Trimtopes (Levine et al. 2014, section 5 and Fig. 4): a convex Voronoi cell, given by its
// face planes n.x <= offset, together with the surface triangles of the object that cross the
// cell. The solid part of a trimtope is the part of its cell behind those triangles, on the side
// of the cell's Voronoi site V, which always lies inside the object.
//
// The paper's four cases for a ray that enters the cell from outside at the point P:
//   A  the ray crosses no triangle inside the cell, and the secondary ray from P to V crosses a
//      forward-facing triangle first (P lies outside the object): a miss;
//   B  the ray crosses no triangle inside the cell, and the secondary ray from P to V crosses no
//      triangle or a backward-facing one first (P lies inside the object): the hit is P, on a
//      face of the cell;
//   C  the first triangle the ray crosses inside the cell is forward facing: the hit is there;
//   D  the first triangle the ray crosses inside the cell is backward facing (the ray was inside
//      the object from P on): the hit is P again.
// "Forward facing" means the triangle's outward side (the side away from the object) faces the
// ray. The paper orients the mesh by V (it lies above V); here the orientation comes from the
// object's closed, outward-oriented surface mesh (counter-clockwise seen from outside), which
// agrees with the paper's wherever the surface inside the cell lies on one side of V and stays
// right where the surface folds inside a cell.
// Rays that start inside the cell (tmin past the entry, e.g. the internal rays of glass) are not
// among the paper's cases; they follow the same idea with the ray's start point in place of P:
// the first triangle crossing is the first crossing of the solid's surface (an entry from
// outside, an exit from inside); without one, the start point is classified by the secondary
// ray to V and an inside start leaves through the cell's exit face.
#pragma once

#include "render/geometry.h"

namespace pd {

// Which of the cases above a trimtope test took.
enum TrimtopeCase : uint8_t {
  kTrimNone = 0,  // the ray's line misses the cell, or the cell lies outside (tmin, ...)
  kTrimA,
  kTrimB,
  kTrimC,
  kTrimD,
  kTrimInsideTriangle,  // started inside the cell: hit at the first triangle crossing
  kTrimInsideExit,      // started inside the cell and inside the object: hit at the cell's exit
  kTrimInsideMiss,      // started inside the cell, outside the object, no triangle crossing
};

// Trimtope i's planes are plane_normal/plane_offset[plane_start[i] .. plane_start[i + 1]),
// its triangles tri_vertex[3 k .. 3 k + 2] for k in [tri_start[i], tri_start[i + 1]).
struct TrimtopesView {
  ArrayView<const Vec3> site;  // Voronoi site V, inside the object
  ArrayView<const int32_t> plane_start;
  ArrayView<const Vec3> plane_normal;  // outward (need not be unit length)
  ArrayView<const real> plane_offset;  // inside: dot(normal, x) <= offset
  ArrayView<const int32_t> tri_start;
  ArrayView<const Vec3> tri_vertex;  // counter-clockwise seen from outside the object
  ArrayView<const Box> box;          // bounds of the solid part (kd-tree build)
};

// Barycentric slack of the triangle test: float round-off must not open cracks along the edges
// shared by two triangles, so each triangle is very slightly enlarged.
constexpr real kTriangleEdgeSlack = real(1e-5);

// The line o + t d against triangle (a, b, c) (Moller-Trumbore): the crossing parameter t and
// the unnormalised geometric normal cross(b - a, c - a). False when the line is parallel to the
// triangle or passes outside it.
PD_HD inline bool line_triangle(Vec3 o, Vec3 d, Vec3 a, Vec3 b, Vec3 c, real* t, Vec3* normal) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 h = cross(d, e2);
  const real det = dot(e1, h);
  if (det == 0) return false;
  const real inv = real(1) / det;
  const Vec3 s = o - a;
  const real u = inv * dot(s, h);
  if (u < -kTriangleEdgeSlack || u > 1 + kTriangleEdgeSlack) return false;
  const Vec3 q = cross(s, e1);
  const real v = inv * dot(d, q);
  if (v < -kTriangleEdgeSlack || u + v > 1 + kTriangleEdgeSlack) return false;
  *t = inv * dot(e2, q);
  *normal = cross(e1, e2);
  return true;
}

// The first crossing of trimtope i's triangles by the line o + t d with t in (ta, tb]: its t and
// the triangle's unnormalised outward normal. Ties go to the first triangle listed.
PD_HD inline bool first_triangle(const TrimtopesView& v, int32_t i, Vec3 o, Vec3 d, real ta, real tb, real* t,
                                 Vec3* normal) {
  bool found = false;
  real best = tb;  // the nearest crossing so far, kept here and written once at the end
  Vec3 best_normal{0, 0, 0};
  for (int32_t k = v.tri_start[i]; k < v.tri_start[i + 1]; ++k) {
    const Vec3* p = v.tri_vertex.sub(3 * int64_t(k), 3).data();
    real tk;
    Vec3 nk;
    if (!line_triangle(o, d, p[0], p[1], p[2], &tk, &nk)) continue;
    if (tk > ta && tk <= tb && (!found || tk < best)) {
      found = true;
      best = tk;
      best_normal = nk;
    }
  }
  if (found) {
    *t = best;
    *normal = best_normal;
  }
  return found;
}

// The parameter interval [t0, t1] of the line inside the convex cell of trimtope i, with the
// (unnormalised) normals of the entry and exit faces. A line parallel to a face plane must lie
// strictly inside it. False when the line misses the cell.
PD_HD inline bool cell_interval(const TrimtopesView& v, int32_t i, const Ray& r, real* t0, real* t1, Vec3* n0,
                                Vec3* n1) {
  *t0 = -INFINITY;
  *t1 = INFINITY;
  *n0 = *n1 = Vec3{0, 0, 0};
  for (int32_t f = v.plane_start[i]; f < v.plane_start[i + 1]; ++f) {
    const Vec3 n = v.plane_normal[f];
    const real denom = dot(n, r.d);
    const real dist = v.plane_offset[f] - dot(n, r.o);  // > 0 when the origin is inside this plane
    if (denom == 0) {
      if (dist <= 0) return false;
      continue;
    }
    const real t = dist / denom;
    if (denom < 0) {
      if (t > *t0) {
        *t0 = t;
        *n0 = n;
      }
    } else if (t < *t1) {
      *t1 = t;
      *n1 = n;
    }
  }
  return *t0 <= *t1;
}

// Is the point p (inside trimtope i's cell) inside the object? The secondary ray of the paper:
// the first triangle crossed on the way from p to the site V decides; none, or a backward-facing
// one, means inside.
PD_HD inline bool inside_object(const TrimtopesView& v, int32_t i, Vec3 p) {
  const Vec3 to_site = v.site[i] - p;
  real t;
  Vec3 n;
  if (!first_triangle(v, i, p, to_site, real(0), real(1), &t, &n)) return true;
  return dot(n, to_site) > 0;
}

// First crossing of trimtope i's solid surface with t in (tmin, tmax] and its outward unit
// normal, as for the other primitives (primitives.h); `which` (optional) receives the case.
// Every t is computed without reference to tmax, so the result does not depend on it.
PD_HD inline bool intersect_trimtope(const TrimtopesView& v, int32_t i, const Ray& r, SurfaceHit* hit,
                                     TrimtopeCase* which = nullptr) {
  TrimtopeCase c = kTrimNone;
  real t0, t1, t = 0;
  Vec3 n0, n1, n{0, 0, 0};
  if (cell_interval(v, i, r, &t0, &t1, &n0, &n1) && t1 > r.tmin) {
    const bool from_outside = t0 > r.tmin;
    const real ts = from_outside ? t0 : r.tmin;  // P, or the ray's start inside the cell
    real tt;
    Vec3 nt;
    if (first_triangle(v, i, r.o, r.d, ts, t1, &tt, &nt)) {
      if (from_outside) {
        c = dot(nt, r.d) < 0 ? kTrimC : kTrimD;
        t = c == kTrimC ? tt : t0;
        n = c == kTrimC ? nt : n0;
      } else {
        c = kTrimInsideTriangle;
        t = tt;
        n = nt;
      }
    } else if (inside_object(v, i, r.o + ts * r.d)) {
      c = from_outside ? kTrimB : kTrimInsideExit;
      t = from_outside ? t0 : t1;
      n = from_outside ? n0 : n1;
    } else {
      c = from_outside ? kTrimA : kTrimInsideMiss;
    }
  }
  if (which) *which = c;
  if (c == kTrimNone || c == kTrimA || c == kTrimInsideMiss || !(t <= r.tmax)) return false;
  hit->t = t;
  hit->normal = normalize(n);
  return true;
}

// From a point inside trimtope i's solid at parameter r.tmin, where the ray leaves the solid:
// the first triangle crossing, else the cell's exit face. False when the line misses the cell
// or leaves it before tmin.
PD_HD inline bool exit_trimtope(const TrimtopesView& v, int32_t i, const Ray& r, SurfaceHit* hit) {
  real t0, t1;
  Vec3 n0, n1;
  if (!cell_interval(v, i, r, &t0, &t1, &n0, &n1) || !(t1 > r.tmin)) return false;
  real tt;
  Vec3 nt;
  const bool tri = first_triangle(v, i, r.o, r.d, rmax(t0, r.tmin), t1, &tt, &nt);
  hit->t = tri ? tt : t1;
  Vec3 n = normalize(tri ? nt : n1);
  if (dot(n, r.d) < 0) n = -n;  // the exit side faces along the ray
  hit->normal = n;
  return true;
}

// Is the point p inside trimtope i's solid: inside every face plane and on V's side of the
// surface?
PD_HD inline bool trimtope_contains(const TrimtopesView& v, int32_t i, Vec3 p) {
  for (int32_t f = v.plane_start[i]; f < v.plane_start[i + 1]; ++f)
    if (!(dot(v.plane_normal[f], p) < v.plane_offset[f])) return false;
  return inside_object(v, i, p);
}

}  // namespace pd
