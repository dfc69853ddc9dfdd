// Embree as the oracle (render/embree_scene.h; built only with Embree): the renderer's kd-tree
// traversal and Embree's BVH over the same primitives, triangulated, see the same image: hit or
// miss equal and depth within 1e-4 relative on at least 99.9% of the pixels, for random cubes,
// tetrahedra and turned cubes and for a lattice block of touching cubes.
#include "render/embree_scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/kdtree.h"
#include "render/traverse.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

struct Agreement {
  int64_t pixels = 0, hits = 0, agree = 0;
};

// Pixel centres of a width x height view: our first hit against Embree's.
Agreement compare_with_embree(const PrimitiveSet& prims, const Camera& camera, int width, int height) {
  const KdTree tree = build_kdtree(prims.bounds());
  const EmbreeScene embree(prims);
  EXPECT_EQ(embree.triangles(), size_t(12 * (prims.cube_center.size() + prims.ocube_center.size()) +
                                       4 * (prims.tet_vertex.size() / 4)));
  const CameraFrame frame = camera_frame(camera, width, height);
  const std::vector<float> theirs = embree.trace_primary(frame, 1).depth;
  Agreement a;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Ray r = camera_ray(frame, real(x) + real(0.5), real(y) + real(0.5));
      const Hit h = traverse_short_stack<kRenderStackSize>(tree.view(), prims.view(), r);
      const float t = theirs[size_t(y) * size_t(width) + size_t(x)];
      ++a.pixels;
      a.hits += h.prim >= 0;
      const bool same = h.prim < 0 ? std::isinf(t) : std::fabs(double(t) - double(h.t)) <= 1e-4 * double(h.t);
      a.agree += same;
    }
  return a;
}

TEST(EmbreeOracle, RandomCubesTetsAndTurnedCubesLookTheSame) {
  Random rng(21);
  PrimitiveSet prims = testing::random_scene(20, 800, 800);
  testing::add_random_oriented_cubes(prims, rng, 600);
  Camera camera;
  camera.eye = {real(2.2), real(1.6), real(2.8)};
  camera.vfov_degrees = 45;
  const Agreement a = compare_with_embree(prims, camera, 400, 300);
  EXPECT_GT(a.hits, a.pixels / 3);
  EXPECT_GE(double(a.agree), 0.999 * double(a.pixels)) << a.pixels - a.agree << " pixels differ";
  std::printf("%lld of %lld pixels differ\n", (long long)(a.pixels - a.agree), (long long)a.pixels);
}

TEST(EmbreeOracle, LatticeBlockLooksTheSame) {
  const PrimitiveSet prims = testing::lattice_scene(30, 10, 30, real(0.1));
  Camera camera;
  camera.eye = {real(4.2), real(2.6), real(4.6)};
  camera.look_at = {real(1.5), real(0.5), real(1.5)};
  camera.vfov_degrees = 40;
  const Agreement a = compare_with_embree(prims, camera, 400, 300);
  EXPECT_GT(a.hits, a.pixels / 4);
  EXPECT_GE(double(a.agree), 0.999 * double(a.pixels)) << a.pixels - a.agree << " pixels differ";
  std::printf("%lld of %lld pixels differ\n", (long long)(a.pixels - a.agree), (long long)a.pixels);
}

}  // namespace
}  // namespace pd
