// Named looks of bodies in renders (render/looks.h): each name a surface and a colour, a palette
// for bodies without one, damage colours only when asked for.
#include "render/looks.h"

#include <gtest/gtest.h>

namespace pd {
namespace {

TEST(Looks, EveryNameIsALookAndOnlyThose) {
  ASSERT_FALSE(look_names().empty());
  for (const std::string& name : look_names()) {
    const std::optional<BodyLook> l = named_look(name);
    ASSERT_TRUE(l) << name;
    for (real c : {l->albedo.x, l->albedo.y, l->albedo.z}) {
      EXPECT_GE(c, 0) << name;
      EXPECT_LE(c, 1) << name;
    }
  }
  EXPECT_EQ(named_look("glass")->surface, kMaterialGlass);
  EXPECT_EQ(named_look("clay")->surface, kMaterialOpaque);
  EXPECT_FALSE(named_look("marble"));
  EXPECT_FALSE(named_look(""));
}

TEST(Looks, DefaultPaletteSeparatesBodies) {
  const BodyLook a = default_look(0, false), b = default_look(1, false);
  EXPECT_NE(a.albedo.x, b.albedo.x);
  EXPECT_EQ(a.surface, kMaterialOpaque);
  EXPECT_EQ(default_look(0, true).surface, kMaterialGlass);
  EXPECT_GE(default_look(-1, false).albedo.x, 0);  // any body id maps into the palette
}

TEST(Looks, DamageTintsRedOnlyOnRequest) {
  const BodyLook clay = *named_look("clay");
  const Vec3 plain = particle_color(clay, 1, false);
  EXPECT_EQ(plain.x, clay.albedo.x);
  EXPECT_EQ(plain.z, clay.albedo.z);
  const Vec3 intact = particle_color(clay, 0, true), hurt = particle_color(clay, 1, true);
  EXPECT_EQ(intact.x, clay.albedo.x);
  EXPECT_GT(hurt.x - hurt.z, intact.x - intact.z);
}

TEST(Looks, RunLooksFallBackToTheDefaultLook) {
  RunLooks looks;
  looks.bodies = {std::nullopt, named_look("steel")};
  EXPECT_EQ(looks.of(0).albedo.x, default_look(0, false).albedo.x);
  EXPECT_EQ(looks.of(1).albedo.x, named_look("steel")->albedo.x);
  EXPECT_EQ(looks.of(7).albedo.x, default_look(7, false).albedo.x);  // past the list
  looks.glass = true;
  EXPECT_EQ(looks.of(0).surface, kMaterialGlass);
  EXPECT_EQ(looks.of(1).surface, kMaterialOpaque);  // a look of its own keeps its surface
}

}  // namespace
}  // namespace pd
