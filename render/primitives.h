// The raytracer's solid primitives, one per particle: axis-aligned cubes, oriented cubes (a cube
// turned by its fragment's rotation), tetrahedra and trimtopes (Voronoi cells trimmed by the
// object's surface, trimtope.h); and triangles, pieces of a closed surface drawn in place of the
// elements it covers (the crack mesh, host/app/mesh_surface.h). A triangle has no solid of its own:
// counter-clockwise seen from outside, its geometric normal points out of the material.
// Storage is structure-of-arrays (PrimitivesView: plain pointers passed by value to kernels);
// primitive i is of kind[i] and its data is entry slot[i] of that kind's arrays.
//
// Every intersection reports the first crossing of the primitive's surface with t in
// (tmin, tmax] together with the outward unit normal of the crossed face: the entry face for
// a ray starting outside, the exit face for a ray starting inside (dot(normal, d) > 0 then).
// The hit parameter is computed independently of tmax, so the same ray gives the same t
// bit for bit wherever it is tested (the kd-tree tests rely on that).
#pragma once

#include "render/geometry.h"
#include "render/trimtope.h"

namespace pd {

enum PrimKind : uint8_t {
  kPrimCube = 0,
  kPrimTet = 1,
  kPrimTrimtope = 2,
  kPrimOrientedCube = 3,
  kPrimTriangle = 4
};

// A tetrahedron's face plane: dot(n, x) = w, n unnormalised and outward.
struct alignas(4 * sizeof(real)) TetPlane {
  Vec3 n;
  real w;
};

struct PrimitivesView {
  int32_t n = 0;
  ArrayView<const uint8_t> kind;  // PrimKind
  ArrayView<const int32_t> slot;  // index into the arrays of that kind
  ArrayView<const Vec3> cube_center;
  ArrayView<const real> cube_half;      // half the side length
  ArrayView<const Vec3> tet_vertex;     // 4 consecutive vertices per tetrahedron
  ArrayView<const TetPlane> tet_plane;  // its 4 face planes (tet_planes)
  ArrayView<const Vec3> ocube_center;
  ArrayView<const real> ocube_half;
  ArrayView<const Vec3> ocube_axis;  // 3 consecutive unit axes per oriented cube (orthonormal)
  ArrayView<const Vec3> tri_vertex;  // 3 consecutive vertices per triangle (counter-clockwise from outside)
  ArrayView<const Vec3> tri_normal;  // 3 consecutive unit shading normals per triangle, one per vertex
  TrimtopesView trim;
};

// Picks the entry crossing t0 when it lies in (tmin, tmax], else the exit crossing t1 when the
// ray starts inside; the caller has checked t0 <= t1.
PD_HD inline bool first_crossing(const Ray& r, real t0, real t1, bool* exiting, real* t) {
  if (t0 > r.tmin) {
    *exiting = false;
    *t = t0;
    return t0 <= r.tmax;
  }
  *exiting = true;
  *t = t1;
  return t1 > r.tmin && t1 <= r.tmax;
}

// Cube of centre c and half side h: slab test. The box is c - h .. c + h per axis, the same
// expressions primitive_bounds uses, so faces coincide exactly with kd-tree split planes.
PD_HD inline bool intersect_cube(const Ray& r, Vec3 c, real h, SurfaceHit* hit) {
  real t0, t1;
  int entry_axis, exit_axis;
  const Vec3 lo{c.x - h, c.y - h, c.z - h}, hi{c.x + h, c.y + h, c.z + h};
  if (!line_box_interval(r, lo, hi, &t0, &t1, &entry_axis, &exit_axis)) return false;
  bool exiting;
  if (!first_crossing(r, t0, t1, &exiting, &hit->t)) return false;
  // Outward normal: against d on the entry face, along d on the exit face.
  const int axis = exiting ? exit_axis : entry_axis;
  const real s = (axis_of(r.d, axis) > 0) == exiting ? real(1) : real(-1);
  hit->normal = {axis == 0 ? s : real(0), axis == 1 ? s : real(0), axis == 2 ? s : real(0)};
  return true;
}

// The ray in the frame of an oriented cube of centre c and orthonormal axes a[0..2]: origin and
// direction projected on the axes. The frame is orthonormal, so t is the same in both frames.
PD_HD inline Ray to_cube_frame(const Ray& r, Vec3 c, const Vec3* a) {
  const Vec3 q = r.o - c;
  return make_ray({dot(q, a[0]), dot(q, a[1]), dot(q, a[2])},
                  {dot(r.d, a[0]), dot(r.d, a[1]), dot(r.d, a[2])}, r.tmin, r.tmax);
}

// Oriented cube: the slab test in its own frame, where it is the box [-h, h]^3; the normal is
// the crossed face's axis turned back into the world.
PD_HD inline bool intersect_oriented_cube(const Ray& r, Vec3 c, real h, const Vec3* a, SurfaceHit* hit) {
  const Ray l = to_cube_frame(r, c, a);
  real t0, t1;
  int entry_axis, exit_axis;
  if (!line_box_interval(l, {-h, -h, -h}, {h, h, h}, &t0, &t1, &entry_axis, &exit_axis)) return false;
  bool exiting;
  if (!first_crossing(l, t0, t1, &exiting, &hit->t)) return false;
  const int axis = exiting ? exit_axis : entry_axis;
  const real s = (axis_of(l.d, axis) > 0) == exiting ? real(1) : real(-1);
  hit->normal = s * a[axis];
  return true;
}

// Bounds of an oriented cube: per world axis k, h (|a0_k| + |a1_k| + |a2_k|), widened by a
// millionth of the coordinates' size so that round-off in the frame change cannot put a hit
// outside the box the kd-tree holds it in.
PD_HD inline Box oriented_cube_bounds(Vec3 c, real h, const Vec3* a) {
  const Vec3 e{h * (std::fabs(a[0].x) + std::fabs(a[1].x) + std::fabs(a[2].x)),
               h * (std::fabs(a[0].y) + std::fabs(a[1].y) + std::fabs(a[2].y)),
               h * (std::fabs(a[0].z) + std::fabs(a[1].z) + std::fabs(a[2].z))};
  const real pad = real(1e-6) * (rmax(std::fabs(c.x), rmax(std::fabs(c.y), std::fabs(c.z))) + 2 * h);
  const Vec3 w{e.x + pad, e.y + pad, e.z + pad};
  return {c - w, c + w};
}

// Face f of tetrahedron v[0..3], the one opposite vertex f: the other three vertices in
// ascending index order. With the vertices stored in one global order (PrimitiveSet::add_tet),
// two tetrahedra sharing a face compute its plane from the same points in the same order, and
// the ray's crossing of it is the same float in both: no crack between them.
PD_HD inline void tet_face(const Vec3* v, int f, Vec3* a, Vec3* b, Vec3* c) {
  *a = v[f == 0 ? 1 : 0];
  *b = v[f <= 1 ? 2 : 1];
  *c = v[f <= 2 ? 3 : 2];
}

// The four face planes of tetrahedron v[0..3] (either orientation), face f opposite vertex f,
// computed from tet_face's points: two tetrahedra sharing a face get the same plane up to an
// exact sign flip, so a ray crosses it at the same t in both.
PD_HD inline void tet_planes(const Vec3* v, TetPlane* plane) {
  for (int f = 0; f < 4; ++f) {
    Vec3 a, b, c;
    tet_face(v, f, &a, &b, &c);
    Vec3 n = cross(b - a, c - a);
    if (dot(n, v[f] - a) > 0) n = -n;
    plane[f] = {n, dot(n, a)};
  }
}

// dist / denom, the ray's crossing of a face plane. On the GPU the fast division (2 ulp, a
// reciprocal and a product): it is odd in both arguments like the exact one, so a face shared by
// two tetrahedra, whose plane differs between them by an exact sign flip, is still crossed at the
// same t in both.
PD_HD inline real face_crossing(real dist, real denom) {
#if defined(__CUDA_ARCH__)
  if constexpr (sizeof(real) == sizeof(float)) return __fdividef(dist, denom);
#endif
  return dist / denom;
}

// The parameter interval [t0, t1] of the line inside the tetrahedron of face planes
// plane[0..3], with the unnormalised outward normals of the entry and exit faces: the line
// clipped against the four planes. A line parallel to a face plane must lie strictly inside it.
PD_HD inline bool tet_interval(const Ray& r, const TetPlane* plane, real* t0, real* t1, Vec3* n0, Vec3* n1) {
  *t0 = -INFINITY;
  *t1 = INFINITY;
  *n0 = *n1 = Vec3{0, 0, 0};
  for (int f = 0; f < 4; ++f) {
    const TetPlane pl = plane[f];
    const real denom = dot(pl.n, r.d);
    const real dist = pl.w - dot(pl.n, r.o);  // > 0 when the origin is inside this face
    if (denom == 0) {
      if (dist <= 0) return false;
      continue;
    }
    const real t = face_crossing(dist, denom);
    if (denom < 0) {
      if (t > *t0) {
        *t0 = t;
        *n0 = pl.n;
      }
    } else if (t < *t1) {
      *t1 = t;
      *n1 = pl.n;
    }
  }
  return *t0 <= *t1;
}

// The tetrahedron of face planes plane[0..3]: the first crossing of its faces.
PD_HD inline bool intersect_tet(const Ray& r, const TetPlane* plane, SurfaceHit* hit) {
  real t0, t1;
  Vec3 n0, n1;
  if (!tet_interval(r, plane, &t0, &t1, &n0, &n1)) return false;
  bool exiting;
  if (!first_crossing(r, t0, t1, &exiting, &hit->t)) return false;
  hit->normal = normalize(exiting ? n1 : n0);
  return true;
}

// The line's crossing of triangle v[0..2], watertight (Woop, Benthin and Wald 2013, "Watertight
// ray/triangle intersection"): the triangle is sheared into the frame where the ray runs along +z,
// and the 2D edge functions of the crossing decide inside or out. Two triangles sharing an edge
// compute its edge function from the same two vertices, the one the exact negation of the other,
// so a ray through the edge hits at least one of them. On a hit: the line parameter *t (any sign)
// and the barycentric weights b[0..2] of the vertices.
PD_HD inline bool line_triangle(const Ray& r, const Vec3* v, real* t, real* b) {
  // The axis of the direction's largest component becomes z; x and y follow cyclically, swapped
  // when d points down that axis so that the winding is kept.
  const real ax = std::fabs(r.d.x), ay = std::fabs(r.d.y), az = std::fabs(r.d.z);
  const int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (axis_of(r.d, kz) < 0) {
    const int swap = kx;
    kx = ky;
    ky = swap;
  }
  const real dz = axis_of(r.d, kz);
  const real sx = axis_of(r.d, kx) / dz, sy = axis_of(r.d, ky) / dz, sz = real(1) / dz;
  // The vertices relative to the origin, sheared.
  real x[3], y[3], z[3];
  for (int k = 0; k < 3; ++k) {
    const Vec3 a = v[k] - r.o;
    z[k] = axis_of(a, kz);
    x[k] = axis_of(a, kx) - sx * z[k];
    y[k] = axis_of(a, ky) - sy * z[k];
  }
  // Edge functions: u of the edge opposite vertex 0, and so on.
  const real u = x[2] * y[1] - y[2] * x[1];
  const real w1 = x[0] * y[2] - y[0] * x[2];
  const real w2 = x[1] * y[0] - y[1] * x[0];
  if ((u < 0 || w1 < 0 || w2 < 0) && (u > 0 || w1 > 0 || w2 > 0)) return false;
  const real det = u + w1 + w2;
  if (det == 0) return false;
  const real inv = real(1) / det;
  *t = (u * z[0] + w1 * z[1] + w2 * z[2]) * sz * inv;
  b[0] = u * inv;
  b[1] = w1 * inv;
  b[2] = w2 * inv;
  return true;
}

// The unit geometric normal of triangle v[0..2]: out of the material for a counter-clockwise one.
PD_HD inline Vec3 triangle_normal(const Vec3* v) {
  return normalize(cross(v[1] - v[0], v[2] - v[0]));
}

// The shading normal at barycentric weights b of a triangle of geometric normal ng and vertex
// normals n[0..2], seen along d: the interpolated vertex normals, mirrored through the triangle's
// plane when they point to the other side of it, and the geometric normal itself where the smooth
// one would face the ray from the other side than the triangle does (grazing rays at silhouettes;
// the renderer decides entry or exit by that side).
PD_HD inline Vec3 triangle_shading_normal(Vec3 ng, const Vec3* n, const real* b, Vec3 d) {
  Vec3 s = b[0] * n[0] + b[1] * n[1] + b[2] * n[2];
  const real len = length(s);
  if (!(len > 0)) return ng;
  s = (real(1) / len) * s;
  const real side = dot(s, ng);
  if (side < 0) s = s - (2 * side) * ng;
  return (dot(s, d) > 0) == (dot(ng, d) > 0) ? s : ng;
}

// Triangle v[0..2] with vertex normals n[0..2]: the crossing in (tmin, tmax] with the smooth
// outward normal (entry or exit alike: the surface is crossed once).
PD_HD inline bool intersect_triangle(const Ray& r, const Vec3* v, const Vec3* n, SurfaceHit* hit) {
  real t, b[3];
  if (!line_triangle(r, v, &t, b) || !(t > r.tmin) || !(t <= r.tmax)) return false;
  hit->t = t;
  hit->normal = triangle_shading_normal(triangle_normal(v), n, b, r.d);
  return true;
}

// Bounds of triangle v[0..2], widened by a millionth of the coordinates' size so that round-off
// in the sheared test cannot put a hit outside the box the kd-tree holds it in.
PD_HD inline Box triangle_bounds(const Vec3* v) {
  const Vec3 lo = vmin(v[0], vmin(v[1], v[2])), hi = vmax(v[0], vmax(v[1], v[2]));
  const real size =
      rmax(rmax(std::fabs(lo.x), std::fabs(hi.x)),
           rmax(rmax(std::fabs(lo.y), std::fabs(hi.y)), rmax(std::fabs(lo.z), std::fabs(hi.z))));
  const real pad = real(1e-6) * size;
  const Vec3 w{pad, pad, pad};
  return {lo - w, hi + w};
}

PD_HD inline bool intersect_primitive(const PrimitivesView& p, int32_t i, const Ray& r, SurfaceHit* hit) {
  const int32_t s = p.slot[i];
  if (p.kind[i] == kPrimCube) return intersect_cube(r, p.cube_center[s], p.cube_half[s], hit);
  if (p.kind[i] == kPrimTrimtope) return intersect_trimtope(p.trim, s, r, hit);
  if (p.kind[i] == kPrimTriangle)
    return intersect_triangle(r, p.tri_vertex.sub(3 * int64_t(s), 3).data(),
                              p.tri_normal.sub(3 * int64_t(s), 3).data(), hit);
  if (p.kind[i] == kPrimOrientedCube)
    return intersect_oriented_cube(r, p.ocube_center[s], p.ocube_half[s],
                                   p.ocube_axis.sub(3 * int64_t(s), 3).data(), hit);
  return intersect_tet(r, p.tet_plane.sub(4 * int64_t(s), 4).data(), hit);
}

PD_HD inline Box primitive_bounds(const PrimitivesView& p, int32_t i) {
  const int32_t s = p.slot[i];
  if (p.kind[i] == kPrimCube) {
    const Vec3 c = p.cube_center[s];
    const real h = p.cube_half[s];
    return {{c.x - h, c.y - h, c.z - h}, {c.x + h, c.y + h, c.z + h}};
  }
  if (p.kind[i] == kPrimTrimtope) return p.trim.box[s];
  if (p.kind[i] == kPrimTriangle) return triangle_bounds(p.tri_vertex.sub(3 * int64_t(s), 3).data());
  if (p.kind[i] == kPrimOrientedCube)
    return oriented_cube_bounds(p.ocube_center[s], p.ocube_half[s],
                                p.ocube_axis.sub(3 * int64_t(s), 3).data());
  const Vec3* v = p.tet_vertex.sub(4 * int64_t(s), 4).data();
  return {vmin(vmin(v[0], v[1]), vmin(v[2], v[3])), vmax(vmax(v[0], v[1]), vmax(v[2], v[3]))};
}

// For a ray whose point at r.tmin lies inside primitive i: where it leaves the primitive's solid,
// with the outward unit normal there (dot(normal, d) >= 0). Used to walk through a connected
// collection of touching elements (union_walk.h). False when the ray's line misses the
// primitive or leaves it at or before tmin, and for a triangle, which has no solid (a ray inside
// a closed triangle surface leaves it at the surface's next crossing, union_walk.h).
PD_HD inline bool primitive_exit(const PrimitivesView& p, int32_t i, const Ray& r, SurfaceHit* hit) {
  const int32_t s = p.slot[i];
  if (p.kind[i] == kPrimTriangle) return false;
  if (p.kind[i] == kPrimTrimtope) return exit_trimtope(p.trim, s, r, hit);
  real t0, t1;
  Vec3 n;
  if (p.kind[i] == kPrimCube) {
    const Vec3 c = p.cube_center[s];
    const real h = p.cube_half[s];
    int entry_axis, exit_axis;
    if (!line_box_interval(r, {c.x - h, c.y - h, c.z - h}, {c.x + h, c.y + h, c.z + h}, &t0, &t1, &entry_axis,
                           &exit_axis) ||
        exit_axis < 0)
      return false;
    const real sign = axis_of(r.d, exit_axis) > 0 ? real(1) : real(-1);
    n = {exit_axis == 0 ? sign : real(0), exit_axis == 1 ? sign : real(0), exit_axis == 2 ? sign : real(0)};
  } else if (p.kind[i] == kPrimOrientedCube) {
    const Vec3* a = p.ocube_axis.sub(3 * int64_t(s), 3).data();
    const real h = p.ocube_half[s];
    const Ray l = to_cube_frame(r, p.ocube_center[s], a);
    int entry_axis, exit_axis;
    if (!line_box_interval(l, {-h, -h, -h}, {h, h, h}, &t0, &t1, &entry_axis, &exit_axis) || exit_axis < 0)
      return false;
    n = (axis_of(l.d, exit_axis) > 0 ? real(1) : real(-1)) * a[exit_axis];
  } else {
    Vec3 n0;
    if (!tet_interval(r, p.tet_plane.sub(4 * int64_t(s), 4).data(), &t0, &t1, &n0, &n)) return false;
  }
  if (!(t1 > r.tmin) || !(t1 < INFINITY)) return false;
  hit->t = t1;
  hit->normal = normalize(n);
  return true;
}

// Is the point x strictly inside primitive i's solid? Never for a triangle, which has none.
PD_HD inline bool primitive_contains(const PrimitivesView& p, int32_t i, Vec3 x) {
  const int32_t s = p.slot[i];
  if (p.kind[i] == kPrimTriangle) return false;
  if (p.kind[i] == kPrimCube) {
    const Vec3 c = p.cube_center[s];
    const real h = p.cube_half[s];
    return std::fabs(x.x - c.x) < h && std::fabs(x.y - c.y) < h && std::fabs(x.z - c.z) < h;
  }
  if (p.kind[i] == kPrimTrimtope) return trimtope_contains(p.trim, s, x);
  if (p.kind[i] == kPrimOrientedCube) {
    const Vec3* a = p.ocube_axis.sub(3 * int64_t(s), 3).data();
    const Vec3 q = x - p.ocube_center[s];
    const real h = p.ocube_half[s];
    return std::fabs(dot(q, a[0])) < h && std::fabs(dot(q, a[1])) < h && std::fabs(dot(q, a[2])) < h;
  }
  const TetPlane* plane = p.tet_plane.sub(4 * int64_t(s), 4).data();
  for (int f = 0; f < 4; ++f)
    if (!(dot(plane[f].n, x) < plane[f].w)) return false;
  return true;
}

}  // namespace pd
