// Rays through a connected collection of elements (Levine sec. 5): elements that touch or
// overlap form one solid (a CSG union), so a ray inside glass must not refract at the faces
// between them. From inside element e the ray goes to e's exit; if a point just beyond that exit
// lies inside another element, the union goes on and the ray continues to that element's exit
// (the farthest, when several contain the point); otherwise the ray leaves the collection there,
// and that last element's face gives the exit normal.
//
// "Just beyond": `gap` past the face, measured along its normal (touching faces agree to float
// round-off; strained bodies open gaps of a fraction of a percent of the element size, which
// `gap` should cover, while real cracks are wider).
//
// A triangle is a piece of a closed surface (the crack mesh) with no solid of its own: a ray that
// entered through one leaves at the surface's next crossing, the nearest triangle beyond the
// entry, wherever it lies; the elements are not walked.
#pragma once

#include "render/kdtree.h"
#include "render/primitives.h"
#include "render/traverse.h"

namespace pd {

// The element containing the point x whose exit along the ray lies farthest (r.tmin: the
// parameter of x on the ray), or -1. Visits the kd-tree leaves holding x: one below or above each
// split, both when x lies on it.
PD_HD inline int32_t farthest_containing(const KdTreeView& tree, const PrimitivesView& prims, const Ray& r,
                                         Vec3 x, SurfaceHit* exit_hit) {
  const Box& b = tree.bounds;
  if (!(x.x >= b.lo.x && x.x <= b.hi.x && x.y >= b.lo.y && x.y <= b.hi.y && x.z >= b.lo.z && x.z <= b.hi.z))
    return -1;
  int32_t best = -1;
  uint32_t stack[kKdMaxDepth];
  int top = 0;
  uint32_t node = 0;
  for (;;) {
    KdNode n = tree.nodes[node];
    while (!n.is_leaf()) {
      const real xa = axis_of(x, n.axis());
      if (xa == n.split && top < kKdMaxDepth) stack[top++] = n.above_child();
      node = xa > n.split ? n.above_child() : node + 1;
      n = tree.nodes[node];
    }
    for (uint32_t k = 0; k < n.prim_count(); ++k) {
      const int32_t id = int32_t(tree.prim_index[n.first_prim + k]);
      if (!primitive_contains(prims, id, x)) continue;
      SurfaceHit h;
      if (!primitive_exit(prims, id, r, &h)) continue;
      if (best < 0 || h.t > exit_hit->t) {
        best = id;
        *exit_hit = h;
      }
    }
    if (top == 0) return best;
    node = stack[--top];
  }
}

// Where the union leaves a ray that starts inside element `first` at r.o (r.tmin slightly above
// 0 so the entry face is not found again).
struct UnionExit {
  int32_t last = -1;     // the last element of the collection crossed; -1: no exit found
  real t = 0;            // the exit's ray parameter
  Vec3 normal{0, 0, 0};  // outward unit normal of the last element's exit face
  int32_t elements = 0;  // elements crossed, `first` included
};

constexpr int32_t kMaxUnionSteps = 4096;  // elements crossed by one ray at most

// The leaf visit of surface_exit: the nearest of the leaf's triangle hits (ties: smaller id).
struct IntersectLeafTriangles {
  const KdTreeView& tree;
  const PrimitivesView& prims;
  const Ray& ray;
  PD_HD void operator()(KdNode leaf, Hit* best) const {
    for (uint32_t k = 0; k < leaf.prim_count(); ++k) {
      const int32_t id = int32_t(tree.prim_index[leaf.first_prim + k]);
      if (prims.kind[id] != kPrimTriangle) continue;
      Ray r = ray;
      if (best->prim >= 0) r.tmax = best->t;
      SurfaceHit h;
      if (!intersect_primitive(prims, id, r, &h)) continue;
      if (best->prim < 0 || h.t < best->t || (h.t == best->t && id < best->prim)) *best = {id, h.t, h.normal};
    }
  }
};

// Where a ray inside a closed triangle surface (entered at r.o, r.tmin past the entry) leaves it:
// the nearest triangle crossing beyond r.tmin, its normal turned along the ray.
PD_HD inline UnionExit surface_exit(const KdTreeView& tree, const PrimitivesView& prims, const Ray& r) {
  UnionExit out;
  const Hit h = walk_short_stack<kRenderStackSize>(tree, r, IntersectLeafTriangles{tree, prims, r});
  if (h.prim < 0) return out;
  out.last = h.prim;
  out.t = h.t;
  out.normal = dot(h.normal, r.d) < 0 ? -h.normal : h.normal;
  out.elements = 1;
  return out;
}

PD_HD inline UnionExit union_exit(const KdTreeView& tree, const PrimitivesView& prims, const Ray& r,
                                  int32_t first, real gap) {
  if (prims.kind[first] == kPrimTriangle) return surface_exit(tree, prims, r);
  UnionExit out;
  SurfaceHit h;
  if (!primitive_exit(prims, first, r, &h)) return out;
  int32_t current = first;
  for (int32_t step = 1; step <= kMaxUnionSteps; ++step) {
    out.last = current;
    out.t = h.t;
    out.normal = h.normal;
    out.elements = step;
    // Probe `gap` beyond the exit face (along its normal; at most 10 gaps along the ray).
    const real along = gap / rmax(dot(h.normal, r.d), real(0.1));
    Ray probe = r;
    probe.tmin = h.t + along;
    SurfaceHit next;
    const int32_t j = farthest_containing(tree, prims, probe, r.o + probe.tmin * r.d, &next);
    if (j < 0 || !(next.t > h.t)) return out;
    current = j;
    h = next;
  }
  return out;
}

}  // namespace pd
