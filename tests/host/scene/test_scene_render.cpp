// The [render] block (host/scene/scene_render.h, parse_render in scene_loader.cpp): every key
// parsed, defaults, paths relative to the scene file, and each mistake a one-line SceneError
// naming the file, the key and what is allowed.
#include <gtest/gtest.h>

#include <string>

#include "host/scene/scene.h"

namespace pd {
namespace {

const std::string kFile = "scenes/test_render.toml";
const std::string kMinimal = R"(
[materials.glass]
density = 2440
bulk_modulus = 3.3e10
strain_limit = 0.0005

[[bodies]]
size = [0.1, 0.1, 0.1]
spacing = 0.01
material = "glass"
)";

// The message names the file and the dotted key, says what is allowed and stays on one line.
// `top` goes before the minimal scene, `render_block` after it.
void expect_error(const std::string& render_block, const std::string& key, const std::string& fragment,
                  const std::string& top = "") {
  std::string message = "no SceneError";
  try {
    parse_scene(top + kMinimal + render_block, kFile);
  } catch (const SceneError& e) {
    message = e.what();
  }
  EXPECT_EQ(message.rfind(kFile + ": " + key + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("(allowed: "), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

TEST(SceneRender, EveryKeyParses) {
  const Scene s = parse_scene(kMinimal + R"(
[render]
eye = [1, 2, 3]
look_at = [0, 0.5, 0]
vfov = 50
width = 640
height = 360
spp = 8
material = "glass"
ior = 1.33
environment = "maps/studio.hdr"
every = 5
surface = "mesh"
smooth_cracks = 4
)",
                              kFile);
  ASSERT_TRUE(s.render);
  const SceneRender& r = *s.render;
  EXPECT_EQ(*r.eye, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(*r.look_at, (std::array<double, 3>{0, 0.5, 0}));
  EXPECT_EQ(r.vfov, 50);
  EXPECT_EQ(r.width, 640);
  EXPECT_EQ(r.height, 360);
  EXPECT_EQ(r.spp, 8);
  EXPECT_EQ(r.material, "glass");
  EXPECT_DOUBLE_EQ(r.ior, 1.33);
  EXPECT_EQ(r.environment, "maps/studio.hdr");
  EXPECT_EQ(r.environment_path, "scenes/maps/studio.hdr");  // relative to the scene's folder
  EXPECT_EQ(r.every, 5);
  EXPECT_EQ(r.surface, "mesh");
  EXPECT_EQ(r.smooth_cracks, 4);
}

TEST(SceneRender, AbsentBlockMeansNoRenderingAndEmptyBlockTheDefaults) {
  EXPECT_FALSE(parse_scene(kMinimal, kFile).render);
  const Scene s = parse_scene(kMinimal + "[render]\n", kFile);
  ASSERT_TRUE(s.render);
  const SceneRender& r = *s.render;
  EXPECT_FALSE(r.eye);
  EXPECT_FALSE(r.look_at);
  EXPECT_EQ(r.vfov, 35);
  EXPECT_EQ(r.width, 1280);
  EXPECT_EQ(r.height, 720);
  EXPECT_EQ(r.spp, 4);
  EXPECT_EQ(r.material, "opaque");
  EXPECT_EQ(r.ior, 1.5);
  EXPECT_EQ(r.environment, "sky");
  EXPECT_EQ(r.environment_path, "");
  EXPECT_EQ(r.every, 1);
  EXPECT_EQ(r.surface, "elements");
  EXPECT_EQ(r.smooth_cracks, 2);
  const Scene absolute = parse_scene(kMinimal + "[render]\nenvironment = \"/maps/sky.hdr\"\n", kFile);
  EXPECT_EQ(absolute.render->environment_path, "/maps/sky.hdr");
}

TEST(SceneRender, MistakesNameTheKeyAndWhatIsAllowed) {
  expect_error("[render]\nfov = 40\n", "render.fov", "allowed: eye, look_at, vfov");
  expect_error("[render]\neye = [1, 2]\n", "render.eye", "expected 3 numbers");
  expect_error("[render]\neye = [1, 1, 1]\nlook_at = [1, 1, 1]\n", "render.look_at", "equals eye");
  expect_error("[render]\nvfov = 180\n", "render.vfov", "a number in (0, 180)");
  expect_error("[render]\nwidth = 8\n", "render.width", "an integer >= 16");
  expect_error("[render]\nheight = 20000\n", "render.height", "an integer in [16, 16384]");
  expect_error("[render]\nwidth = 640.5\n", "render.width", "expected an integer");
  expect_error("[render]\nspp = 0\n", "render.spp", ">= 1");
  expect_error("[render]\nspp = 2048\n", "render.spp", "an integer in [1, 1024]");
  expect_error("[render]\nmaterial = \"wood\"\n", "render.material", "\"opaque\", \"glass\"");
  expect_error("[render]\nior = 0.9\n", "render.ior", "a number in [1, 4]");
  expect_error("[render]\nenvironment = \"\"\n", "render.environment", "the path is empty");
  expect_error("[render]\nenvironment = 3\n", "render.environment", "expected a string");
  expect_error("[render]\nevery = -1\n", "render.every", "an integer >= 0");
  expect_error("[render]\nsurface = \"smooth\"\n", "render.surface", "\"elements\", \"mesh\"");
  expect_error("[render]\nsmooth_cracks = 101\n", "render.smooth_cracks", "an integer in [0, 100]");
  expect_error("", "render", "expected a table", "render = 1\n");
  expect_error("[output]\nbinary = false\n[render]\n", "render", "output.binary = true");
}

}  // namespace
}  // namespace pd
