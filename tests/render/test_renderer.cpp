// The renderer's stop question (RenderSettings::stop): asked between parts of a frame, it leaves
// the image bit for bit what it is without it, or stops the frame unfinished.
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <memory>

namespace pd {
namespace {

TEST(Renderer, AStopQuestionChangesNoPixelOrStopsTheFrame) {
  RenderSettings s;
  s.width = 64;
  s.height = 48;
  s.spp = 2;
  PrimitiveSet prims;
  prims.add_cube({0, 0, 0}, 1);
  prims.add_cube({1.5, 0.5, 0}, real(0.5));
  const RenderScene scene = make_render_scene(prims, {{0.5, 0.2, 0.2}, {0.2, 0.5, 0.2}});
  Camera camera;
  camera.eye = {3, 4, 5};
  const std::unique_ptr<Renderer> r = make_renderer(false);
  const RenderResult whole = r->render_frame(scene, camera, s);
  EXPECT_FALSE(whole.stopped);
  int asked = 0;
  s.stop = [&asked] { return ++asked < 0; };  // asked, never stopping
  const RenderResult parts = r->render_frame(scene, camera, s);
  EXPECT_FALSE(parts.stopped);
  EXPECT_GT(asked, 1);
  EXPECT_EQ(parts.image.rgb, whole.image.rgb);
  s.stop = [] { return true; };
  EXPECT_TRUE(r->render_frame(scene, camera, s).stopped);
}

}  // namespace
}  // namespace pd
