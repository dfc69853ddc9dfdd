// A kd-tree over primitive bounding boxes for the raytracer (Levine et al. 2014, section 5):
// built on the host with the surface-area heuristic (pbrt-v3's sorted-edge sweep, here with
// edges sorted once and kept sorted while partitioning), flattened depth-first into an array
// of 8-byte nodes that both backends traverse (traverse.h).
//
// Splitting rule, which the traversal mirrors: a node with split plane s on axis a sends a
// primitive with box [lo, hi] below when lo < s (or the box is flat at hi <= s) and above when
// hi > s. Boxes touching the plane from one side therefore stay on that side only, so a
// lattice of face-adjacent cubes is separated without duplicating any of them.
#pragma once

#include <vector>

#include "render/geometry.h"

namespace pd {

// Depth cap of every tree; the full-stack traversal sizes its stack with it.
constexpr int kKdMaxDepth = 64;

// pbrt's KdAccelNode layout. Interior node: split position, low two bits of `bits` the axis,
// the rest the index of the above child (the below child follows its parent). Leaf: low bits
// 3, the rest the primitive count; first_prim indexes KdTreeView::prim_index.
struct KdNode {
  union {
    float split;
    uint32_t first_prim;
  };
  uint32_t bits;

  PD_HD bool is_leaf() const { return (bits & 3u) == 3u; }
  PD_HD int axis() const { return int(bits & 3u); }
  PD_HD uint32_t above_child() const { return bits >> 2; }
  PD_HD uint32_t prim_count() const { return bits >> 2; }

  static KdNode interior(int axis, float split_position, uint32_t above) {
    KdNode n;
    n.split = split_position;
    n.bits = (above << 2) | uint32_t(axis);
    return n;
  }
  static KdNode leaf(uint32_t first, uint32_t count) {
    KdNode n;
    n.first_prim = first;
    n.bits = (count << 2) | 3u;
    return n;
  }
};
static_assert(sizeof(KdNode) == 8, "kd-tree nodes are 8 bytes");

// What the traversal reads; node 0 is the root.
struct KdTreeView {
  ArrayView<const KdNode> nodes;
  ArrayView<const uint32_t> prim_index;
  Box bounds{{0, 0, 0}, {0, 0, 0}};  // union of all primitive boxes
};

struct KdBuildOptions {
  enum class Split { kSah, kMedian };  // kMedian: object median on the longest axis (baseline)
  Split split = Split::kSah;
  // pbrt-v3's SAH constants.
  double traversal_cost = 1;
  double intersect_cost = 80;
  double empty_bonus = 0.5;
  int max_leaf_prims = 1;  // nodes with at most this many primitives (at least 1) become leaves
  int max_depth = -1;      // -1: round(8 + 1.3 log2 N); always capped at kKdMaxDepth
  int threads = 0;         // OpenMP threads of the build (subtrees as tasks); 0: all; the tree is the same
};

struct KdTreeStats {
  double build_seconds = 0;
  int64_t nodes = 0, leaves = 0, empty_leaves = 0;
  int64_t prim_refs = 0;  // entries of prim_index (a primitive counts once per leaf holding it)
  int depth = 0;          // deepest leaf
  int depth_limit = 0;
  int threads = 1;  // threads the build used
};

struct KdTree {
  std::vector<KdNode> nodes;
  std::vector<uint32_t> prim_index;
  Box bounds{{0, 0, 0}, {0, 0, 0}};
  KdTreeStats stats;

  KdTreeView view() const { return {view_of(nodes), view_of(prim_index), bounds}; }
};

// Builds the tree over primitives 0..boxes.size()-1. Throws std::length_error past 2^30
// nodes or primitive references (the node encoding's limit).
KdTree build_kdtree(const std::vector<Box>& boxes, const KdBuildOptions& options = {});

// The tree over the primitives whose `leave_out` flag is 0 (an empty `leave_out`: all), with
// prim_index holding their indices among all of `boxes`.
KdTree build_kdtree_without(const std::vector<Box>& boxes, const std::vector<uint8_t>& leave_out,
                            const KdBuildOptions& options = {});

}  // namespace pd
