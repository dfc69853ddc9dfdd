// Short-stack kd-tree traversal against the brute-force nearest hit: identical primitive, t
// and normal for every ray, for stack sizes 1..8 and the full stack.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "render/kdtree.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

using testing::random_direction;
using testing::uniform;
using testing::uniform_point;

void set_axis(Vec3& v, int a, real value) {
  (a == 0 ? v.x : (a == 1 ? v.y : v.z)) = value;
}

// The split planes of a tree (axis, position), to aim rays at.
std::vector<std::pair<int, float>> split_planes(const KdTree& t) {
  std::vector<std::pair<int, float>> planes;
  for (const KdNode& n : t.nodes)
    if (!n.is_leaf()) planes.push_back({n.axis(), n.split});
  return planes;
}

// Random rays of every awkward kind for `scene`.
std::vector<Ray> awkward_rays(const PrimitiveSet& scene, const KdTree& tree, uint64_t seed, int per_kind) {
  Random rng(seed);
  const std::vector<std::pair<int, float>> planes = split_planes(tree);
  auto plane = [&] { return planes[size_t(rng.uniform() * double(planes.size())) % planes.size()]; };
  const Box& b = tree.bounds;
  auto point = [&] {
    const Vec3 u = uniform_point(rng, -0.2, 1.2);
    return Vec3{b.lo.x + u.x * (b.hi.x - b.lo.x), b.lo.y + u.y * (b.hi.y - b.lo.y),
                b.lo.z + u.z * (b.hi.z - b.lo.z)};
  };
  std::vector<Ray> rays;
  auto add = [&](Vec3 o, Vec3 d, real tmin = 0, real tmax = INFINITY) {
    rays.push_back(make_ray(o, d, tmin, tmax));
  };
  const PrimitivesView v = scene.view();
  for (int k = 0; k < per_kind; ++k) {
    // General rays, some with a finite interval.
    add(point(), random_direction(rng));
    add(point(), random_direction(rng), uniform(rng, 0, 0.5), uniform(rng, 0.5, 3));
    // Starting inside a primitive (at its box centre).
    const Box pb = primitive_bounds(v, int32_t(rng.uniform() * v.n) % v.n);
    add(real(0.5) * (pb.lo + pb.hi), random_direction(rng));
    // Lying in a split plane; parallel to it just off it; grazing it; starting on it.
    const auto [a, s] = plane();
    Vec3 o = point(), d = random_direction(rng);
    set_axis(o, a, s);
    set_axis(d, a, 0);
    add(o, normalize(d));
    Vec3 o_off = o;
    set_axis(o_off, a, std::nextafter(s, rng.uniform() < 0.5 ? -INFINITY : INFINITY));
    add(o_off, normalize(d));
    Vec3 d_graze = d;
    set_axis(d_graze, a, uniform(rng, -1e-5, 1e-5));
    add(o, normalize(d_graze));
    add(o, random_direction(rng));
    // Along a coordinate axis, through the plane's offset line.
    Vec3 axis_dir{0, 0, 0};
    set_axis(axis_dir, (a + 1 + int(rng.uniform() * 2)) % 3, rng.uniform() < 0.5 ? -1 : 1);
    add(o, axis_dir);
  }
  return rays;
}

struct Mismatches {
  int count = 0;
  int64_t restarts = 0;
};

template <int K>
void compare_stack(const KdTree& tree, const PrimitivesView& v, const std::vector<Ray>& rays,
                   const std::vector<Hit>& expected, Mismatches* m) {
  TraversalStats stats;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Hit h = traverse_short_stack<K>(tree.view(), v, rays[i], &stats);
    const Hit& e = expected[i];
    const bool same =
        h.prim == e.prim && (e.prim < 0 || (h.t == e.t && h.normal.x == e.normal.x &&
                                            h.normal.y == e.normal.y && h.normal.z == e.normal.z));
    if (!same && ++m->count <= 5) {
      const Ray& r = rays[i];
      ADD_FAILURE() << "K=" << K << " ray " << i << " o=(" << r.o.x << "," << r.o.y << "," << r.o.z << ") d=("
                    << r.d.x << "," << r.d.y << "," << r.d.z << "): tree " << h.prim << " t=" << h.t
                    << ", brute force " << e.prim << " t=" << e.t;
    }
  }
  m->restarts += stats.restarts;
}

template <int... K>
void compare_all(const KdTree& tree, const PrimitivesView& v, const std::vector<Ray>& rays,
                 const std::vector<Hit>& expected, std::integer_sequence<int, K...>, Mismatches* small) {
  (compare_stack<K + 1>(tree, v, rays, expected, small), ...);
}

// Every stack size reproduces the brute-force hits and the full stack never restarts;
// returns the restarts of the short stacks.
int64_t check_scene(const PrimitiveSet& scene, uint64_t seed, int per_kind) {
  const KdTree tree = build_kdtree(scene.bounds());
  const PrimitivesView v = scene.view();
  const std::vector<Ray> rays = awkward_rays(scene, tree, seed, per_kind);
  std::vector<Hit> expected;
  int hits = 0;
  for (const Ray& r : rays) {
    expected.push_back(testing::brute_force_hit(v, r));
    hits += expected.back().prim >= 0;
  }
  EXPECT_GT(hits, int(rays.size()) / 4);
  Mismatches small;
  compare_all(tree, v, rays, expected, std::make_integer_sequence<int, 8>(), &small);
  EXPECT_EQ(small.count, 0);
  Mismatches full;
  compare_stack<kKdMaxDepth>(tree, v, rays, expected, &full);
  EXPECT_EQ(full.count, 0);
  EXPECT_EQ(full.restarts, 0);
  return small.restarts;
}

TEST(ShortStackTraversal, MatchesBruteForceOnRandomCubesAndTets) {
  EXPECT_GT(check_scene(testing::random_scene(1, 300, 300), 101, 500), 0);
}

TEST(ShortStackTraversal, MatchesBruteForceOnDenseOverlappingScene) {
  EXPECT_GT(check_scene(testing::random_scene(2, 1500, 500), 102, 300), 0);
}

TEST(ShortStackTraversal, MatchesBruteForceOnLatticesWithSharedFaces) {
  check_scene(testing::lattice_scene(12, 9, 7, real(0.125)), 103, 400);  // faces coincide exactly
  check_scene(testing::lattice_scene(11, 8, 9, real(0.1)), 104, 400);    // faces off by an ulp
}

TEST(ShortStackTraversal, MatchesBruteForceOnRandomTrimtopeScenes) {
  EXPECT_GT(check_scene(testing::random_trimtope_scene(5, 600, 0, 0), 105, 400), 0);
  EXPECT_GT(check_scene(testing::random_trimtope_scene(6, 500, 300, 300), 106, 300), 0);
}

TEST(ShortStackTraversal, MatchesBruteForceOnRandomOrientedCubes) {
  Random rng(8);
  PrimitiveSet alone;
  testing::add_random_oriented_cubes(alone, rng, 700);
  EXPECT_GT(check_scene(alone, 107, 400), 0);
  PrimitiveSet mixed = testing::random_scene(9, 300, 300);
  testing::add_random_oriented_cubes(mixed, rng, 400);
  EXPECT_GT(check_scene(mixed, 108, 300), 0);
}

TEST(ShortStackTraversal, MatchesBruteForceOnATurnedLattice) {
  Random rng(10);
  Vec3 axis[3];
  testing::random_axes(rng, axis);
  check_scene(testing::oriented_lattice_scene(10, 8, 7, real(0.125), axis), 109, 400);
}

TEST(ShortStackTraversal, MatchesBruteForceOnTriangles) {
  // Loose random triangles, alone and among cubes and tets.
  Random rng(11);
  PrimitiveSet alone;
  testing::add_random_triangles(alone, rng, 800);
  EXPECT_GT(check_scene(alone, 110, 400), 0);
  PrimitiveSet mixed = testing::random_scene(12, 300, 300);
  testing::add_random_triangles(mixed, rng, 600);
  EXPECT_GT(check_scene(mixed, 111, 300), 0);
  // Closed boxes of triangles whose faces lie on shared planes (a lattice of touching boxes).
  PrimitiveSet boxes;
  const real s = real(0.125);
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 7; ++i)
        testing::add_box_triangles(boxes, {i * s, j * s, k * s}, {(i + 1) * s, (j + 1) * s, (k + 1) * s});
  check_scene(boxes, 112, 400);
}

TEST(ShortStackTraversal, FullStackVisitsNoMoreNodesThanRestarts) {
  const PrimitiveSet scene = testing::random_scene(3, 2000, 0);
  const KdTree tree = build_kdtree(scene.bounds());
  Random rng(7);
  TraversalStats one, full;
  for (int k = 0; k < 2000; ++k) {
    const Ray r = make_ray(uniform_point(rng, -1.5, 1.5), random_direction(rng), 0, INFINITY);
    traverse_short_stack<1>(tree.view(), scene.view(), r, &one);
    traverse_full_stack(tree.view(), scene.view(), r, &full);
  }
  EXPECT_GT(one.restarts, 0);
  EXPECT_GT(one.nodes, full.nodes);
  EXPECT_EQ(full.restarts, 0);
}

}  // namespace
}  // namespace pd
