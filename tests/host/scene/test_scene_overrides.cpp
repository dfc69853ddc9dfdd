// --set KEY=VALUE overrides on a scene's TOML document (host/scene/scene_overrides.h).
#include <gtest/gtest.h>

#include <string>

#include "host/scene/scene.h"
#include "host/scene/scene_overrides.h"

namespace pd {
namespace {

TEST(SceneOverrides, SetNestedKeysCreatingTables) {
  toml::table root = toml::parse("[world]\ngravity = [0, -9.81, 0]\n");
  apply_override(root, "world.gravity = [0, 0, -1]", "s.toml");
  apply_override(root, "materials.glass.density=2500", "s.toml");
  EXPECT_EQ(root["world"]["gravity"][2].value<double>(), -1.0);
  EXPECT_EQ(root["materials"]["glass"]["density"].value<int64_t>(), 2500);
}

TEST(SceneOverrides, ReplaceAnElementOrAddATableOnePastTheEnd) {
  toml::table root = toml::parse("v = [1, 2]\n[[bodies]]\nspacing = 1\n");
  apply_override(root, "v[1]=5", "s.toml");
  EXPECT_EQ(root["v"][1].value<int64_t>(), 5);
  apply_override(root, "bodies[1].spacing=2", "s.toml");
  ASSERT_EQ(root["bodies"].as_array()->size(), 2u);
  EXPECT_EQ(root["bodies"][1]["spacing"].value<int64_t>(), 2);
  apply_override(root, "shards[0].size=0.01", "s.toml");  // none in the file: the first is added
  EXPECT_EQ(root["shards"][0]["size"].value<double>(), 0.01);
}

TEST(SceneOverrides, MistakesNameTheSetting) {
  const auto error_of = [](const std::string& setting) {
    toml::table root = toml::parse("v = [1, 2]\n[simulation]\nframes = 3\n");
    try {
      apply_override(root, setting, "s.toml");
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), "s.toml");
      return e.key() + " | " + e.what();
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("simulation.frames").find("--set simulation.frames | "), std::string::npos);
  EXPECT_NE(error_of("simulation.frames").find("expected KEY=VALUE"), std::string::npos);
  EXPECT_NE(error_of("v=[1,").find("the value is not TOML"), std::string::npos);
  EXPECT_NE(error_of("v[2]=1").find("'v' has no element 2"), std::string::npos);
  EXPECT_NE(error_of("v[x]=1").find("[x] is not an index"), std::string::npos);
  EXPECT_NE(error_of("v[0=1").find("an unclosed ["), std::string::npos);
  EXPECT_NE(error_of("a..b=1").find("an empty name in the path"), std::string::npos);
  EXPECT_NE(error_of("simulation.frames.x=1").find("not a table"), std::string::npos);
  EXPECT_NE(error_of("v=1\nw=2").find("line break"), std::string::npos);
  EXPECT_NE(error_of("materials.\"a.b=1").find("an unclosed \""), std::string::npos);
  EXPECT_NE(error_of("materials.\"a\"b=1").find("a quoted name followed by 'b'"), std::string::npos);
}

// A name holding a dot, quoted as TOML quotes it.
TEST(SceneOverrides, AQuotedNameMayHoldADot) {
  toml::table root = toml::parse("[materials.\"soda.lime\"]\ndensity = 2500\n");
  apply_override(root, "materials.\"soda.lime\".density=2440", "s.toml");
  EXPECT_EQ(root["materials"]["soda.lime"]["density"].value<int64_t>(), 2440);
}

}  // namespace
}  // namespace pd
