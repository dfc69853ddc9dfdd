#include "render/kdtree.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <omp.h>

namespace pd {

namespace {

constexpr uint32_t kMaxEncoded = 1u << 30;  // 30 bits for child indices and counts
constexpr int64_t kMinTaskPrims = 4096;     // smaller nodes are built serially: not worth a task

// One end of a primitive's box along an axis.
struct Edge {
  float t;
  uint32_t code;  // primitive << 1 | 1 for the lower (start) end, | 0 for the upper (end) end

  uint32_t prim() const { return code >> 1; }
  bool is_start() const { return code & 1u; }
};

// Position order; at equal positions end edges first, so a sweep sees boxes that end at a
// plane before those that start there. Primitive ids break the remaining ties.
bool edge_less(const Edge& a, const Edge& b) {
  if (a.t != b.t) return a.t < b.t;
  if (a.is_start() != b.is_start()) return b.is_start();
  return a.code < b.code;
}

// The primitives of a node as three edge lists, each sorted along its axis.
struct EdgeLists {
  std::vector<Edge> axis[3];
  int64_t prims() const { return int64_t(axis[0].size() / 2); }
};

real lo_of(const Box& b, int a) {
  return axis_of(b.lo, a);
}
real hi_of(const Box& b, int a) {
  return axis_of(b.hi, a);
}
void set_axis(Vec3& v, int a, real value) {
  (a == 0 ? v.x : (a == 1 ? v.y : v.z)) = value;
}

// Which children a box goes to under split s: bit 0 below, bit 1 above (see kdtree.h).
uint8_t sides_of(const Box& b, int a, float s) {
  const real lo = lo_of(b, a), hi = hi_of(b, a);
  return uint8_t((lo < s || hi <= s) ? 1 : 0) | uint8_t(hi > s ? 2 : 0);
}

struct Split {
  int axis = -1;
  float position = 0;
  double cost = INFINITY;
};

// A built subtree: nodes in depth-first order (below child right after its parent), indices
// relative to the subtree's own arrays until it is spliced into its parent's.
struct Subtree {
  std::vector<KdNode> nodes;
  std::vector<uint32_t> prim_index;
  int64_t leaves = 0, empty_leaves = 0;
  int depth = 0;  // deepest leaf (absolute depth)
};

class KdBuilder {
 public:
  // `task_depth`: nodes above this depth build their two children as parallel OpenMP tasks
  // (0: serial). The tree is the same for any task depth.
  KdBuilder(const std::vector<Box>& boxes, const KdBuildOptions& options, int depth_limit, int task_depth)
      : boxes_(boxes), options_(options), depth_limit_(depth_limit), task_depth_(task_depth) {}

  // Builds the subtree for `edges` (consumed) inside `bounds` into `out`: its root is appended
  // to out's nodes, its below subtree follows and its above subtree comes after that.
  void build(EdgeLists& edges, const Box& bounds, int depth, int bad_refines, Subtree* out) {
    const uint32_t index = append_node(out);
    const int64_t n = edges.prims();
    if (n <= std::max(options_.max_leaf_prims, 1) || depth >= depth_limit_)
      return make_leaf(out, index, edges, depth);
    const bool parallel = depth < task_depth_ && n >= kMinTaskPrims;  // near the root: per-axis work as tasks

    // Choose the split; give up (leaf) as pbrt-v3 does when it does not pay off.
    Split s;
    if (options_.split == KdBuildOptions::Split::kSah) {
      s = best_sah_split(edges, bounds, parallel);
      const double leaf_cost = options_.intersect_cost * double(n);
      if (s.cost > leaf_cost) ++bad_refines;
      if (s.axis < 0 || (s.cost > 4 * leaf_cost && n < 16) || bad_refines == 3)
        return make_leaf(out, index, edges, depth);
    } else {
      s = median_split(edges, bounds);
      if (s.axis < 0) return make_leaf(out, index, edges, depth);
    }

    // Partition: every axis list is filtered in order, so children inherit sorted lists.
    if (sides_.empty()) sides_.assign(boxes_.size(), 0);
    for (const Edge& e : edges.axis[0])
      if (e.is_start()) sides_[e.prim()] = sides_of(boxes_[e.prim()], s.axis, s.position);
    EdgeLists below, above;
#pragma omp taskloop default(shared) if (parallel)
    for (int k = 0; k < 3; ++k) {
      for (const Edge& e : edges.axis[k]) {
        const uint8_t side = sides_[e.prim()];
        if (side & 1) below.axis[k].push_back(e);
        if (side & 2) above.axis[k].push_back(e);
      }
      std::vector<Edge>().swap(edges.axis[k]);
    }

    // Recurse: below child right after this node, then the above child.
    Box below_bounds = bounds, above_bounds = bounds;
    set_axis(below_bounds.hi, s.axis, s.position);
    set_axis(above_bounds.lo, s.axis, s.position);
    if (parallel) {
      // Both children at once, each by its own builder (own partition scratch) into its own
      // subtree, then spliced in the serial order.
      Subtree below_tree, above_tree;
#pragma omp task default(shared)
      KdBuilder(boxes_, options_, depth_limit_, task_depth_)
          .build(below, below_bounds, depth + 1, bad_refines, &below_tree);
#pragma omp task default(shared)
      KdBuilder(boxes_, options_, depth_limit_, task_depth_)
          .build(above, above_bounds, depth + 1, bad_refines, &above_tree);
#pragma omp taskwait
      splice(out, below_tree);
      out->nodes[index] = KdNode::interior(s.axis, s.position, uint32_t(out->nodes.size()));
      splice(out, above_tree);
      return;
    }
    build(below, below_bounds, depth + 1, bad_refines, out);
    out->nodes[index] = KdNode::interior(s.axis, s.position, uint32_t(out->nodes.size()));
    build(above, above_bounds, depth + 1, bad_refines, out);
  }

 private:
  static uint32_t append_node(Subtree* out) {
    if (out->nodes.size() >= kMaxEncoded) throw std::length_error("kd-tree: more than 2^30 nodes");
    out->nodes.push_back(KdNode::leaf(0, 0));
    return uint32_t(out->nodes.size() - 1);
  }

  // Appends `sub` to `out`, shifting its child and primitive indices by where it lands.
  static void splice(Subtree* out, const Subtree& sub) {
    const uint32_t node_base = uint32_t(out->nodes.size()), prim_base = uint32_t(out->prim_index.size());
    if (out->nodes.size() + sub.nodes.size() > kMaxEncoded)
      throw std::length_error("kd-tree: more than 2^30 nodes");
    if (out->prim_index.size() + sub.prim_index.size() >= kMaxEncoded)
      throw std::length_error("kd-tree: more than 2^30 references");
    for (KdNode n : sub.nodes) {
      if (n.is_leaf())
        n.first_prim += prim_base;
      else
        n.bits += node_base << 2;
      out->nodes.push_back(n);
    }
    out->prim_index.insert(out->prim_index.end(), sub.prim_index.begin(), sub.prim_index.end());
    out->leaves += sub.leaves;
    out->empty_leaves += sub.empty_leaves;
    out->depth = std::max(out->depth, sub.depth);
  }

  static void make_leaf(Subtree* out, uint32_t index, const EdgeLists& edges, int depth) {
    const size_t first = out->prim_index.size();
    for (const Edge& e : edges.axis[0])
      if (e.is_start()) out->prim_index.push_back(e.prim());
    const size_t count = out->prim_index.size() - first;
    if (out->prim_index.size() >= kMaxEncoded) throw std::length_error("kd-tree: more than 2^30 references");
    out->nodes[index] = KdNode::leaf(uint32_t(first), uint32_t(count));
    ++out->leaves;
    if (count == 0) ++out->empty_leaves;
    out->depth = std::max(out->depth, depth);
  }

  // pbrt-v3's SAH sweep over each axis's sorted edges. Edges at one position are taken
  // together, so the counts match the splitting rule: below = boxes with lo < t, above =
  // boxes with hi > t.
  Split best_sah_split(const EdgeLists& edges, const Box& bounds, bool parallel) const {
    Split per_axis[3];
#pragma omp taskloop default(shared) if (parallel)
    for (int a = 0; a < 3; ++a) per_axis[a] = best_sah_split_on(edges, bounds, a);
    // In axis order with a strict comparison: ties go to the lower axis, as in one sweep.
    Split best;
    for (const Split& s : per_axis)
      if (s.cost < best.cost) best = s;
    return best;
  }

  // The SAH sweep along one axis.
  Split best_sah_split_on(const EdgeLists& edges, const Box& bounds, int a) const {
    Split best;
    const Vec3 ext = bounds.hi - bounds.lo;
    const double dx = ext.x, dy = ext.y, dz = ext.z;
    const double area = 2 * (dx * dy + dy * dz + dz * dx);
    if (!(area > 0)) return best;
    const int64_t n = edges.prims();
    const double d[3] = {dx, dy, dz};
    const double o0 = d[(a + 1) % 3], o1 = d[(a + 2) % 3];
    const double lo = lo_of(bounds, a), hi = hi_of(bounds, a);
    const std::vector<Edge>& e = edges.axis[a];
    int64_t below = 0, above = n;
    for (size_t i = 0; i < e.size();) {
      const float t = e[i].t;
      int64_t starts = 0, ends = 0;
      size_t j = i;
      for (; j < e.size() && e[j].t == t; ++j) ++(e[j].is_start() ? starts : ends);
      above -= ends;
      if (t > lo && t < hi) {
        const double p_below = 2 * (o0 * o1 + (t - lo) * (o0 + o1)) / area;
        const double p_above = 2 * (o0 * o1 + (hi - t) * (o0 + o1)) / area;
        const double bonus = (below == 0 || above == 0) ? options_.empty_bonus : 0;
        const double cost = options_.traversal_cost + options_.intersect_cost * (1 - bonus) *
                                                          (p_below * double(below) + p_above * double(above));
        if (cost < best.cost) best = {a, t, cost};
      }
      below += starts;
      i = j;
    }
    return best;
  }

  // Baseline: the median of box centres along the node's longest axis.
  Split median_split(const EdgeLists& edges, const Box& bounds) const {
    const Vec3 ext = bounds.hi - bounds.lo;
    const int a = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::vector<real> centre;
    for (const Edge& e : edges.axis[0])
      if (e.is_start())
        centre.push_back(real(0.5) * (lo_of(boxes_[e.prim()], a) + hi_of(boxes_[e.prim()], a)));
    auto mid = centre.begin() + centre.size() / 2;
    std::nth_element(centre.begin(), mid, centre.end());
    const float s = float(*mid);
    Split split;
    if (s > lo_of(bounds, a) && s < hi_of(bounds, a)) split = {a, s, 0};
    return split;
  }

  const std::vector<Box>& boxes_;
  const KdBuildOptions& options_;
  int depth_limit_, task_depth_;
  std::vector<uint8_t> sides_;  // per primitive, valid during one partition (allocated on first use)
};

}  // namespace

KdTree build_kdtree(const std::vector<Box>& boxes, const KdBuildOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (boxes.size() >= kMaxEncoded) throw std::length_error("kd-tree: more than 2^30 primitives");
  const int64_t n = int64_t(boxes.size());
  KdTree tree;

  // Root bounds and depth limit.
  if (n > 0) {
    tree.bounds = boxes[0];
    for (const Box& b : boxes) tree.bounds = {vmin(tree.bounds.lo, b.lo), vmax(tree.bounds.hi, b.hi)};
  }
  const int automatic = int(std::lround(8 + 1.3 * std::log2(double(std::max<int64_t>(n, 1)))));
  tree.stats.depth_limit = std::min(options.max_depth < 0 ? automatic : options.max_depth, kKdMaxDepth);

  // Edge lists of the root, sorted once per axis.
  EdgeLists edges;
  const int sort_threads = options.threads > 0 ? std::min(options.threads, 3) : 3;
#pragma omp parallel for schedule(static, 1) num_threads(sort_threads)
  for (int a = 0; a < 3; ++a) {
    std::vector<Edge>& e = edges.axis[a];
    e.resize(2 * size_t(n));
    for (int64_t i = 0; i < n; ++i) {
      e[2 * i] = {float(lo_of(boxes[i], a)), uint32_t(i) << 1 | 1u};
      e[2 * i + 1] = {float(hi_of(boxes[i], a)), uint32_t(i) << 1};
    }
    std::sort(e.begin(), e.end(), edge_less);
  }

  // Build: in parallel below the root when there are threads to use (the same tree either way).
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  int task_depth = 0;
  while (threads > 1 && (1 << task_depth) < 4 * threads) ++task_depth;  // ~4 subtrees per thread
  Subtree root;
  if (task_depth > 0 && n >= 2 * kMinTaskPrims) {
#pragma omp parallel num_threads(threads)
#pragma omp single
    KdBuilder(boxes, options, tree.stats.depth_limit, task_depth).build(edges, tree.bounds, 0, 0, &root);
  } else {
    KdBuilder(boxes, options, tree.stats.depth_limit, 0).build(edges, tree.bounds, 0, 0, &root);
  }
  tree.nodes = std::move(root.nodes);
  tree.prim_index = std::move(root.prim_index);
  tree.stats.leaves = root.leaves;
  tree.stats.empty_leaves = root.empty_leaves;
  tree.stats.depth = root.depth;
  tree.stats.threads = task_depth > 0 ? threads : 1;
  tree.stats.nodes = int64_t(tree.nodes.size());
  tree.stats.prim_refs = int64_t(tree.prim_index.size());
  tree.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return tree;
}

KdTree build_kdtree_without(const std::vector<Box>& boxes, const std::vector<uint8_t>& leave_out,
                            const KdBuildOptions& options) {
  std::vector<uint32_t> kept;
  std::vector<Box> kept_boxes;
  for (size_t i = 0; i < boxes.size(); ++i)
    if (leave_out.empty() || !leave_out[i]) {
      kept.push_back(uint32_t(i));
      kept_boxes.push_back(boxes[i]);
    }
  if (kept.size() == boxes.size()) return build_kdtree(boxes, options);
  KdTree tree = build_kdtree(kept_boxes, options);
  for (uint32_t& p : tree.prim_index) p = kept[p];
  return tree;
}

}  // namespace pd
