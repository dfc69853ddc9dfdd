// Scene smells (host/scene/scene_smells.h): an anchor holding no particle, two bodies of one name,
// a body below the floor and overlapping bodies each give one warning line naming it; a clean scene
// (bodies that merely touch included) gives none.
#include "host/scene/scene_smells.h"

#include <gtest/gtest.h>

#include "host/scene/scene_setup.h"

namespace pd {
namespace {

const std::string kScene = R"(
[simulation]
dt = 1e-7
[world]
floor = true
floor_height = 0.0
[materials.m]
model = "bond_based"
density = 1000
bulk_modulus = 1e9
strain_limit = 1e-3
[[bodies]]
name = "block"
center = [0, 0.05, 0]
size = [0.04, 0.04, 0.04]
spacing = 0.01
material = "m"
)";

std::vector<std::string> smells(const std::string& extra) {
  const Scene scene = parse_scene(kScene + extra, "scene.toml");
  const SetupResult s = setup_scene(scene, SetupOptions(1.0));
  return scene_smells(scene, s.input, s.body_names);
}

TEST(SceneSmells, CleanSceneHasNone) {
  EXPECT_TRUE(smells("").empty());
}

TEST(SceneSmells, EachSmellIsOneLine) {
  const std::vector<std::string> w = smells(R"(
[[bodies]]
name = "block"
center = [0.2, -0.05, 0]
size = [0.04, 0.04, 0.04]
spacing = 0.01
material = "m"
[[anchors]]
box_min = [1, 1, 1]
box_max = [2, 2, 2]
[[anchors]]
box_min = [-0.1, 0, -0.1]
box_max = [0.1, 0.1, 0.1]
)");
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0], "warning: anchors[0]: its box holds no particle, so it does nothing");
  EXPECT_NE(w[1].find("bodies[0] and bodies[1] are both named 'block'"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("body 'block': 64 particles start below the floor (y = 0)"), std::string::npos) << w[2];
  for (const std::string& line : w) EXPECT_EQ(line.find('\n'), std::string::npos);
}

// Bodies that touch face to face are clean; one pushed half into the other is named with the
// particles that overlap.
TEST(SceneSmells, OverlappingBodiesAreNamed) {
  const std::string second = R"(
[[bodies]]
name = "lid"
center = [0, CENTER_Y, 0]
size = [0.04, 0.04, 0.04]
spacing = 0.01
material = "m"
)";
  auto with_lid_at = [&](const std::string& y) {
    std::string text = second;
    text.replace(text.find("CENTER_Y"), 8, y);
    return smells(text);
  };
  EXPECT_TRUE(with_lid_at("0.09").empty());                // touching: the block spans y 0.03 to 0.07
  const std::vector<std::string> w = with_lid_at("0.07");  // two layers of each body coincide
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("warning: bodies 'block' and 'lid' overlap: 64 of their particles"), std::string::npos)
      << w[0];
}

}  // namespace
}  // namespace pd
