// Nearest-hit kd-tree traversal with a short stack (Horn et al. 2007, "Interactive k-D tree
// GPU raytracing"): far children go into a ring buffer of K entries, the oldest overwritten
// when it is full; when it runs dry before the ray has left the scene, traversal restarts at
// the root with tmin advanced to the exit of the last leaf (kd-restart). K = kKdMaxDepth never
// drops an entry: that is the full-stack traversal, the reference the tests compare against.
//
// Conventions matching the build (kdtree.h): a ray lying in a split plane belongs above it,
// as in the half-open slab test of primitives.h. Split crossings are computed as
// (split - o) * inv_d, the expression the cube slab test uses, so a cube face on a split plane
// is crossed at exactly the plane's t and the nearest hit (ties: smallest primitive id) is
// the one a brute-force loop over all primitives finds.
#pragma once

#include "render/kdtree.h"
#include "render/primitives.h"

namespace pd {

constexpr int kRenderStackSize = 4;  // short-stack entries per ray in the renderer

struct Hit {
  int32_t prim = -1;  // -1: no hit
  real t = 0;
  Vec3 normal{0, 0, 0};  // outward normal of the face crossed (primitives.h)
};

// Work counters (tests and tuning).
struct TraversalStats {
  int64_t nodes = 0;     // interior nodes and leaves visited
  int64_t tests = 0;     // primitive intersection tests
  int64_t restarts = 0;  // short-stack restarts from the root
};

// Keeps the nearest of the leaf's primitive hits in `best`; ties go to the smaller id.
PD_HD inline void intersect_leaf(const KdTreeView& tree, const PrimitivesView& prims, KdNode leaf,
                                 const Ray& ray, Hit* best, TraversalStats* stats) {
  const uint32_t count = leaf.prim_count();
  for (uint32_t k = 0; k < count; ++k) {
    const int32_t id = int32_t(tree.prim_index[leaf.first_prim + k]);
    Ray r = ray;
    if (best->prim >= 0) r.tmax = best->t;
    SurfaceHit h;
    if (stats) ++stats->tests;
    if (!intersect_primitive(prims, id, r, &h)) continue;
    if (best->prim < 0 || h.t < best->t || (h.t == best->t && id < best->prim)) {
      best->prim = id;
      best->t = h.t;
      best->normal = h.normal;
    }
  }
}

// The walk itself, whatever the leaves hold: visits the leaves the ray crosses, nearest first, and
// calls visit_leaf(leaf, &best) at each to bring the nearest hit `best` up to date with the leaf's
// contents (the primitives here; the two-level bench enters fragment trees). Stops at the first hit
// that no later leaf can beat.
template <int K, class VisitLeaf>
PD_HD inline Hit walk_short_stack(const KdTreeView& tree, const Ray& ray, const VisitLeaf& visit_leaf,
                                  TraversalStats* stats = nullptr) {
  static_assert(K >= 1, "the short stack needs at least one entry");
  Hit best;
  // The ray's interval inside the scene bounds.
  real t_enter, t_exit;
  int entry_axis, exit_axis;
  if (!line_box_interval(ray, tree.bounds.lo, tree.bounds.hi, &t_enter, &t_exit, &entry_axis, &exit_axis))
    return best;
  t_enter = rmax(t_enter, ray.tmin);
  t_exit = rmin(t_exit, ray.tmax);
  if (t_enter > t_exit) return best;

  struct Entry {
    uint32_t node;
    real tmin, tmax;
  };
  Entry stack[K];
  int top = 0, count = 0;  // ring buffer: next slot, live entries
  uint32_t node = 0;
  real tmin = t_enter, tmax = t_exit;
  for (;;) {
    // Descend to a leaf, pushing the far child whenever the ray reaches both children.
    KdNode n = tree.nodes[node];
    while (!n.is_leaf()) {
      if (stats) ++stats->nodes;
      const int a = n.axis();
      const real o = axis_of(ray.o, a), d = axis_of(ray.d, a), split = n.split;
      const bool below_first = o < split || (o == split && d < 0);
      const uint32_t near_child = below_first ? node + 1 : n.above_child();
      const uint32_t far_child = below_first ? n.above_child() : node + 1;
      const real t_split = (split - o) * axis_of(ray.inv_d, a);
      if (d == 0 || t_split >= tmax || t_split <= 0) {
        node = near_child;  // parallel, or the plane lies beyond this interval or behind the origin
      } else if (t_split <= tmin) {
        node = far_child;  // the ray crossed the plane before entering this node
      } else {
        stack[top] = {far_child, t_split, tmax};
        top = (top + 1) % K;
        count = count < K ? count + 1 : K;
        node = near_child;
        tmax = t_split;
      }
      n = tree.nodes[node];
    }
    if (stats) ++stats->nodes;
    visit_leaf(n, &best);
    // A hit before the leaf's exit is final: everything left lies beyond it. At exactly the exit
    // a primitive of the next leaf may tie, and the smaller id wins, so traversal goes on.
    if (best.prim >= 0 && best.t < tmax) return best;
    if (count > 0) {
      top = (top + K - 1) % K;
      --count;
      node = stack[top].node;
      tmin = stack[top].tmin;
      tmax = stack[top].tmax;
    } else if (tmax < t_exit) {
      if (stats) ++stats->restarts;
      node = 0;
      tmin = tmax;
      tmax = t_exit;
    } else {
      return best;
    }
    if (best.prim >= 0 && best.t < tmin) return best;
  }
}

// The leaf visit of the renderer's traversal: the nearest of the leaf's primitive hits.
struct IntersectLeaf {
  const KdTreeView& tree;
  const PrimitivesView& prims;
  const Ray& ray;
  TraversalStats* stats;
  PD_HD void operator()(KdNode leaf, Hit* best) const { intersect_leaf(tree, prims, leaf, ray, best, stats); }
};

// The nearest primitive hit along `ray`.
template <int K>
PD_HD inline Hit traverse_short_stack(const KdTreeView& tree, const PrimitivesView& prims, const Ray& ray,
                                      TraversalStats* stats = nullptr) {
  return walk_short_stack<K>(tree, ray, IntersectLeaf{tree, prims, ray, stats}, stats);
}

// The reference: the same traversal with a stack as deep as any tree, so it never restarts.
PD_HD inline Hit traverse_full_stack(const KdTreeView& tree, const PrimitivesView& prims, const Ray& ray,
                                     TraversalStats* stats = nullptr) {
  return traverse_short_stack<kKdMaxDepth>(tree, prims, ray, stats);
}

}  // namespace pd
