// The CUDA renderer against the CPU renderer (skipped without a usable GPU; then asking for the
// GPU renderer must fail cleanly).
#include <gtest/gtest.h>

#include <cstdlib>

#include "host/engine.h"
#include "render/renderer.h"
#include "render_scenes.h"

namespace pd {
namespace {

TEST(CudaRenderer, MatchesTheCpuRenderer) {
  std::string why;
  if (!cuda_device_available(&why)) {
    EXPECT_THROW(make_renderer(true), std::runtime_error);
    GTEST_SKIP() << why;
  }
  // Cubes and tets over a lattice block, floor, sun and sky: every shading path.
  PrimitiveSet prims = testing::random_scene(9, 400, 400);
  const PrimitiveSet block = testing::lattice_scene(20, 6, 20, real(0.1));
  for (int32_t i = 0; i < block.size(); ++i)
    prims.add_cube(block.cube_center[i] - Vec3{1, real(1.6), 1}, block.cube_half[i]);
  std::vector<Vec3> albedo;
  Random rng(4);
  for (int32_t i = 0; i < prims.size(); ++i) albedo.push_back(testing::uniform_point(rng, 0.1, 0.9));
  const RenderScene scene = make_render_scene(prims, albedo);
  RenderSettings s;
  s.width = 320;
  s.height = 200;
  s.spp = 2;
  s.floor_y = real(-1.7);
  const Camera camera = frame_box(scene.tree.bounds, s.width, s.height);

  const ImageRGB8 cpu = make_renderer(false)->render_frame(scene, camera, s).image;
  const RenderResult gpu = make_renderer(true)->render_frame(scene, camera, s);
  ASSERT_EQ(gpu.image.rgb.size(), cpu.rgb.size());
  // Fused multiply-adds on the device move some values by an ulp: allow a level of rounding
  // everywhere and a different primitive at a few silhouette pixels.
  int far_off = 0;
  for (size_t i = 0; i < cpu.rgb.size(); ++i)
    far_off += std::abs(int(cpu.rgb[i]) - int(gpu.image.rgb[i])) > 2;
  EXPECT_LE(far_off, int(cpu.rgb.size() / 500)) << far_off << " channel values differ by more than 2";
  EXPECT_GT(gpu.seconds, 0);
}

}  // namespace
}  // namespace pd
