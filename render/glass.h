// Light through a transparent (glass) collection of touching elements (Levine sec. 5): the ray
// refracts where it enters the collection, crosses the touching elements without refracting at
// their shared faces (union_walk.h), and at the face of the last element of the collection it
// either refracts out or, under total internal reflection or when reflection is the stronger
// part, reflects back inside and walks on. Fresnel weights: fresnel.h.
#pragma once

#include "render/fresnel.h"
#include "render/union_walk.h"

namespace pd {

constexpr int32_t kMaxInternalReflections = 8;

// What leaves the collection: the ray that goes on outside and the count of interfaces met.
struct GlassTransit {
  Vec3 point{0, 0, 0};               // where the light leaves the collection
  Vec3 dir{0, 0, 0};                 // unit direction it goes on in
  real weight = 1;                   // product of the Fresnel factors of the branches followed inside
  int32_t last = -1;                 // the element it leaves from; -1: no exit found, or trapped
  int32_t elements = 0;              // element crossings, all walks added
  int32_t internal_reflections = 0;  // reflections at exit faces
};

// Light refracted into element `first` at `entry` going in unit direction `dir` (inside the
// glass of index `ior`), `gap` the union tolerance (union_walk.h). At each exit face it follows
// the stronger Fresnel branch: refraction out, or internal reflection (always under total
// internal reflection); the weaker part is dropped. After kMaxInternalReflections reflections the
// light refracts out where it can; light still trapped then is reported with last = -1.
PD_HD inline GlassTransit glass_transit(const KdTreeView& tree, const PrimitivesView& prims, Vec3 entry,
                                        Vec3 dir, int32_t first, real ior, real gap) {
  GlassTransit out;
  Vec3 o = entry, d = dir;
  int32_t element = first;
  const real start = real(0.01) * gap;  // skips the face the walk starts on
  for (int32_t bounce = 0;; ++bounce) {
    const UnionExit ex = union_exit(tree, prims, make_ray(o, d, start, INFINITY), element, gap);
    if (ex.last < 0) {
      out.last = -1;
      out.point = o;
      out.dir = d;
      return out;
    }
    out.elements += ex.elements;
    out.last = ex.last;
    out.point = o + ex.t * d;
    const Vec3 n = ex.normal;  // outward: along d
    const Fresnel f = fresnel_dielectric(dot(d, n), ior, real(1));
    if (f.transmit > 0 && (f.transmit >= f.reflect || bounce == kMaxInternalReflections)) {
      out.dir = refract(d, -n, ior, real(1), f.cos_t);
      out.weight *= f.transmit;
      return out;
    }
    if (bounce == kMaxInternalReflections) {
      out.last = -1;  // still trapped by total internal reflection
      out.dir = d;
      return out;
    }
    // Internal reflection: back into the last element from its face.
    out.weight *= f.reflect;
    ++out.internal_reflections;
    o = out.point;
    d = normalize(reflect(d, n));
    element = ex.last;
  }
}

}  // namespace pd
