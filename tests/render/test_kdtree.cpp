// kd-tree structure: node encoding, reachability of every primitive, size sanity, and the
// surface-area heuristic against a median split.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "render/kdtree.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

using testing::random_direction;
using testing::uniform_point;

real lo_of(const Box& b, int a) {
  return axis_of(b.lo, a);
}
real hi_of(const Box& b, int a) {
  return axis_of(b.hi, a);
}
Box with_axis(Box b, bool upper, int a, real v) {
  Vec3& p = upper ? b.hi : b.lo;
  (a == 0 ? p.x : (a == 1 ? p.y : p.z)) = v;
  return b;
}

bool leaf_holds(const KdTree& t, const KdNode& leaf, uint32_t prim) {
  const uint32_t* first = t.prim_index.data() + leaf.first_prim;
  return std::find(first, first + leaf.prim_count(), prim) != first + leaf.prim_count();
}

// Walks the tree with each node's region; `visit_leaf(node, region)` for every leaf. Checks
// the structural invariants on the way.
void walk(const KdTree& t, uint32_t node, const Box& region, int depth,
          const std::function<void(const KdNode&, const Box&)>& visit_leaf) {
  ASSERT_LT(node, t.nodes.size());
  ASSERT_LE(depth, t.stats.depth_limit);
  const KdNode n = t.nodes[node];
  if (n.is_leaf()) {
    ASSERT_LE(size_t(n.first_prim) + n.prim_count(), t.prim_index.size());
    return visit_leaf(n, region);
  }
  const int a = n.axis();
  EXPECT_GT(n.split, lo_of(region, a));
  EXPECT_LT(n.split, hi_of(region, a));
  ASSERT_GT(n.above_child(), node + 1);
  walk(t, node + 1, with_axis(region, true, a, n.split), depth + 1, visit_leaf);
  walk(t, n.above_child(), with_axis(region, false, a, n.split), depth + 1, visit_leaf);
}

TEST(KdTree, NodesAreEightBytesAndRoundTrip) {
  EXPECT_EQ(sizeof(KdNode), 8u);
  const KdNode i = KdNode::interior(2, 1.5f, 12345);
  EXPECT_FALSE(i.is_leaf());
  EXPECT_EQ(i.axis(), 2);
  EXPECT_EQ(i.split, 1.5f);
  EXPECT_EQ(i.above_child(), 12345u);
  const KdNode l = KdNode::leaf(777, (1u << 30) - 1);
  EXPECT_TRUE(l.is_leaf());
  EXPECT_EQ(l.first_prim, 777u);
  EXPECT_EQ(l.prim_count(), (1u << 30) - 1);
}

TEST(KdTree, EveryPrimitiveIsInEveryLeafItOverlaps) {
  const PrimitiveSet scene = testing::random_scene(11, 400, 400);
  const std::vector<Box> boxes = scene.bounds();
  const KdTree t = build_kdtree(boxes);
  std::vector<int> leaves_holding(boxes.size(), 0);
  int64_t leaves = 0, refs = 0;
  walk(t, 0, t.bounds, 0, [&](const KdNode& leaf, const Box& region) {
    ++leaves;
    refs += leaf.prim_count();
    for (uint32_t k = 0; k < leaf.prim_count(); ++k) ++leaves_holding[t.prim_index[leaf.first_prim + k]];
    // Any box sharing volume with the leaf region must be listed in it.
    for (uint32_t p = 0; p < boxes.size(); ++p) {
      const Box& b = boxes[p];
      const bool overlaps = b.lo.x < region.hi.x && b.hi.x > region.lo.x && b.lo.y < region.hi.y &&
                            b.hi.y > region.lo.y && b.lo.z < region.hi.z && b.hi.z > region.lo.z;
      if (overlaps) {
        EXPECT_TRUE(leaf_holds(t, leaf, p)) << "primitive " << p;
      }
    }
  });
  for (size_t p = 0; p < boxes.size(); ++p) EXPECT_GE(leaves_holding[p], 1) << "primitive " << p;
  // Sizes: a full binary tree, references within a small factor of the primitive count.
  EXPECT_EQ(t.stats.leaves, leaves);
  EXPECT_EQ(t.stats.nodes, 2 * leaves - 1);
  EXPECT_EQ(int64_t(t.nodes.size()), t.stats.nodes);
  EXPECT_EQ(t.stats.prim_refs, refs);
  EXPECT_LE(refs, 10 * int64_t(boxes.size()));  // overlapping boxes are shared by leaves
  EXPECT_LE(t.stats.depth, t.stats.depth_limit);
  EXPECT_EQ(t.stats.depth_limit, int(std::lround(8 + 1.3 * std::log2(800.0))));
}

TEST(KdTree, LatticeOfTouchingCubesIsSplitWithoutDuplicates) {
  // Dyadic spacing: neighbouring faces coincide exactly.
  const PrimitiveSet lattice = testing::lattice_scene(8, 8, 8, real(0.125));
  const KdTree t = build_kdtree(lattice.bounds());
  EXPECT_EQ(t.stats.prim_refs, 512);
  EXPECT_EQ(t.stats.empty_leaves, 0);
}

TEST(KdTree, DepthLimitAndEmptyScene) {
  const PrimitiveSet scene = testing::random_scene(5, 300, 0);
  KdBuildOptions o;
  o.max_depth = 3;
  const KdTree shallow = build_kdtree(scene.bounds(), o);
  EXPECT_LE(shallow.stats.depth, 3);
  EXPECT_LE(shallow.stats.nodes, 15);

  const KdTree empty = build_kdtree({});
  ASSERT_EQ(empty.nodes.size(), 1u);
  EXPECT_TRUE(empty.nodes[0].is_leaf());
  EXPECT_EQ(empty.nodes[0].prim_count(), 0u);
  const PrimitiveSet none;
  const Hit h = traverse_full_stack(empty.view(), none.view(), make_ray({0, 0, -1}, {0, 0, 1}, 0, INFINITY));
  EXPECT_EQ(h.prim, -1);
}

// Clusters of small cubes in a large, mostly empty volume: the SAH cuts away empty space
// early, a median split does not.
TEST(KdTree, SahVisitsFewerNodesThanMedianSplitOnClusteredScene) {
  Random rng(21);
  PrimitiveSet scene;
  const Vec3 centres[4] = {{-9, -9, -9}, {8, -7, 9}, {-6, 9, 7}, {9, 8, -8}};
  for (const Vec3& c : centres)
    for (int i = 0; i < 500; ++i) scene.add_cube(c + uniform_point(rng, -0.5, 0.5), real(0.01));
  for (int i = 0; i < 20; ++i) scene.add_cube(uniform_point(rng, -10, 10), real(0.05));
  KdBuildOptions median;
  median.split = KdBuildOptions::Split::kMedian;
  const KdTree sah_tree = build_kdtree(scene.bounds());
  const KdTree median_tree = build_kdtree(scene.bounds(), median);

  TraversalStats sah, med;
  for (int k = 0; k < 4000; ++k) {
    // Rays from a sphere around the scene towards random points of a random cluster.
    const Vec3 o = real(30) * random_direction(rng);
    const Vec3 target = centres[k % 4] + uniform_point(rng, -0.6, 0.6);
    const Ray r = make_ray(o, normalize(target - o), 0, INFINITY);
    const Hit a = traverse_full_stack(sah_tree.view(), scene.view(), r, &sah);
    const Hit b = traverse_full_stack(median_tree.view(), scene.view(), r, &med);
    ASSERT_EQ(a.prim, b.prim);
    ASSERT_EQ(a.t, b.t);
  }
  RecordProperty("sah_nodes_per_ray", std::to_string(double(sah.nodes) / 4000));
  RecordProperty("median_nodes_per_ray", std::to_string(double(med.nodes) / 4000));
  EXPECT_LT(double(sah.nodes), 0.8 * double(med.nodes)) << sah.nodes << " vs " << med.nodes;
}

// The parallel build (subtrees and per-axis work as OpenMP tasks) gives the serial build's tree
// node for node, whatever the thread count.
TEST(KdTree, ParallelBuildIsTheSerialTree) {
  const PrimitiveSet scene = testing::random_scene(11, 20000, 10000);
  KdBuildOptions serial;
  serial.threads = 1;
  const KdTree a = build_kdtree(scene.bounds(), serial);
  EXPECT_EQ(a.stats.threads, 1);
  for (int threads : {2, 3, 8}) {
    KdBuildOptions o;
    o.threads = threads;
    const KdTree b = build_kdtree(scene.bounds(), o);
    EXPECT_EQ(b.stats.threads, threads);
    ASSERT_EQ(b.nodes.size(), a.nodes.size()) << threads;
    for (size_t k = 0; k < a.nodes.size(); ++k) {
      ASSERT_EQ(b.nodes[k].bits, a.nodes[k].bits) << "node " << k << ", " << threads << " threads";
      ASSERT_EQ(b.nodes[k].first_prim, a.nodes[k].first_prim)
          << "node " << k << ", " << threads << " threads";
    }
    EXPECT_EQ(b.prim_index, a.prim_index);
    EXPECT_EQ(b.stats.leaves, a.stats.leaves);
    EXPECT_EQ(b.stats.empty_leaves, a.stats.empty_leaves);
    EXPECT_EQ(b.stats.depth, a.stats.depth);
  }
}

}  // namespace
}  // namespace pd
