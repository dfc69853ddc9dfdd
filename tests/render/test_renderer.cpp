// The renderer's stop question (RenderSettings::stop): asked between parts of a big frame, it
// leaves the image bit for bit what it is without it, or stops the frame unfinished.
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <memory>

namespace pd {
namespace {

TEST(Renderer, AStopQuestionChangesNoPixelOrStopsTheFrame) {
  RenderSettings s;  // (big enough for two parts: 2^19 pixels and 2^23 samples and more)
  s.width = 1024;
  s.height = 640;
  s.spp = 13;
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
  EXPECT_EQ(asked, 1);  // (between the two parts)
  EXPECT_EQ(parts.image.rgb, whole.image.rgb);
  s.stop = [] { return true; };
  EXPECT_TRUE(r->render_frame(scene, camera, s).stopped);
}

}  // namespace
}  // namespace pd
