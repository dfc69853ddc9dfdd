// The two-level prototype of bench-render (host/app/bench_two_level.h): blocks of a lattice moved
// apart, traced through a top-level tree into per-fragment rest-space trees, see what one tree
// over the moved primitives sees.
#include "host/app/bench_two_level.h"

#include <gtest/gtest.h>

#include "tests/render/render_scenes.h"

namespace pd {
namespace {

TEST(TwoLevelPrototype, SeesWhatOneRebuiltTreeSees) {
  // 24 x 4 x 24 cubes of side 1/24 in [0, 1] x [0, 1/6] x [0, 1], cut into 3 x 3 fragments.
  const PrimitiveSet prims = testing::lattice_scene(24, 4, 24, real(1.0 / 24));
  Camera camera;
  camera.eye = {real(1.6), real(1.1), real(1.9)};
  camera.look_at = {real(0.5), 0, real(0.5)};
  const TwoLevelReport r = measure_two_level(prims, 24, 4, 24, 1, 9, camera_frame(camera, 160, 120), {});
  EXPECT_EQ(r.fragments, 9);
  EXPECT_GT(r.instances_per_ray, 0.3);  // most rays enter a fragment
  EXPECT_GE(r.agreement, 0.999);
  EXPECT_GT(r.world_build_seconds, 0);
  EXPECT_GT(r.top_build_seconds, 0);
}

}  // namespace
}  // namespace pd
