// Physical ranges checked once the particles exist (host/scene/range_checks.h): keyframed paths
// faster than light and a fracture energy whose critical stretch is not in (0, 1) are refused,
// naming the key.
#include "host/scene/range_checks.h"

#include <gtest/gtest.h>

#include <string>

#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {
namespace {

const std::string kBlock = R"(
[simulation]
dt = 1e-7
[materials.brick]
model = "bond_based"
density = 1900
bulk_modulus = 5e9
[[bodies]]
shape = "box"
size = [0.1, 0.1, 0.1]
spacing = 0.01
material = "brick"
)";

// The key the set-up's SceneError names, or "" when it sets the scene up.
std::string refused_key(const std::string& extra, const std::string& material = "strain_limit = 1e-3\n") {
  std::string text = kBlock;
  text.insert(text.find("[[bodies]]"), material);
  try {
    setup_scene(parse_scene(text + extra, "scene.toml"), SetupOptions(1.0));
  } catch (const SceneError& e) {
    return e.key();
  }
  return "";
}

TEST(RangeChecks, KeyframedPathsBelowTheSpeedOfLight) {
  const std::string anchor = "[[anchors]]\nbox_min = [-1, -1, -1]\nbox_max = [1, 1, 1]\n";
  EXPECT_EQ(refused_key(anchor + "path = [[0, 0, 0, 0], [1e-3, 1, 0, 0]]\n"), "");
  EXPECT_EQ(refused_key(anchor + "path = [[0, 0, 0, 0], [1e-12, 1e3, 0, 0]]\n"), "anchors[0].path");
  EXPECT_EQ(refused_key("[[projectiles]]\nradius = 0.01\nstrength = 1e9\npath = [[0, 0, 1, 0], [1e-9, 0, 1, "
                        "1e3]]\n"),
            "projectiles[0].path");
}

TEST(RangeChecks, AFractureEnergyMustGiveAStretchBelowOne) {
  EXPECT_EQ(refused_key("", "fracture_energy = 10.0\n"), "");
  EXPECT_EQ(refused_key("", "fracture_energy = 1e12\n"), "materials.brick.fracture_energy");
  EXPECT_EQ(refused_key("", "fracture_energy = 1e-300\n"), "materials.brick.fracture_energy");
}

}  // namespace
}  // namespace pd
