// Spherical-harmonic lighting, the sky, the shading model, and uniformity of a diffuse object
// under a constant environment rendered end to end on the CPU.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "render/renderer.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

const double kPiD = 3.14159265358979323846;

TEST(SphericalHarmonics, ConstantEnvironmentHasOnlyTheDcTerm) {
  const real c = real(0.7);
  const Sh9 L = project_sh9([&](Vec3) { return Vec3{c, 2 * c, 3 * c}; });
  // L_00 = c * Y_00 * 4 pi = c * sqrt(4 pi).
  EXPECT_NEAR(L.c[0].x, c * std::sqrt(4 * kPiD), 1e-5);
  EXPECT_NEAR(L.c[0].z, 3 * c * std::sqrt(4 * kPiD), 3e-5);
  for (int k = 1; k < 9; ++k) {
    EXPECT_NEAR(L.c[k].x, 0, 1e-5) << k;
    EXPECT_NEAR(L.c[k].z, 0, 1e-5) << k;
  }
  // Irradiance pi c from every direction.
  Random rng(1);
  for (int i = 0; i < 50; ++i)
    EXPECT_NEAR(sh9_irradiance(L, testing::random_direction(rng)).x, kPiD * c, 1e-5);
}

TEST(SphericalHarmonics, LinearEnvironmentGivesTheCosineConvolution) {
  // Radiance 1 + w.z: L_00 = sqrt(4 pi), L_10 = sqrt(4 pi / 3); irradiance pi + (2 pi / 3) n.z.
  const Sh9 L = project_sh9([](Vec3 w) { return Vec3{1 + w.z, 1 + w.z, 1 + w.z}; });
  EXPECT_NEAR(L.c[0].x, std::sqrt(4 * kPiD), 1e-5);
  EXPECT_NEAR(L.c[2].x, std::sqrt(4 * kPiD / 3), 1e-5);
  for (int k : {1, 3, 4, 5, 6, 7, 8}) EXPECT_NEAR(L.c[k].x, 0, 1e-5) << k;
  Random rng(2);
  for (int i = 0; i < 50; ++i) {
    const Vec3 n = testing::random_direction(rng);
    EXPECT_NEAR(sh9_irradiance(L, n).x, kPiD + 2 * kPiD / 3 * n.z, 1e-4);
  }
}

TEST(SphericalHarmonics, QuadraticLobeMatchesTheAnalyticConvolution) {
  // Radiance x y = Y_2-2 / 1.092548, so L_2-2 = 1 / 1.092548 and E(n) = A_2 L_2-2 Y_2-2(n) =
  // (pi / 4) n.x n.y.
  const Sh9 L = project_sh9([](Vec3 w) { return Vec3{w.x * w.y, 0, 0}; });
  Random rng(3);
  for (int i = 0; i < 50; ++i) {
    const Vec3 n = testing::random_direction(rng);
    EXPECT_NEAR(sh9_irradiance(L, n).x, kPiD / 4 * n.x * n.y, 1e-5);
  }
}

TEST(Sky, SunAddsItsIrradianceTowardsTheSun) {
  Sky sky;
  sky.zenith = sky.horizon = sky.ground = {0, 0, 0};
  sky.sun_direction = {0, 1, 0};
  sky.sun_irradiance = {2, 2, 2};
  const Sh9 L = sky_sh9(sky);
  // A point source of irradiance E in the order-2 approximation: E sum_l A_l (2l + 1) / (4 pi)
  // = E (1/4 + 1/2 + 5/16) facing it, E (1/4 - 1/2 + 5/16) facing away (ringing).
  EXPECT_NEAR(sh9_irradiance(L, {0, 1, 0}).x, 2 * (0.25 + 0.5 + 5.0 / 16), 1e-4);
  EXPECT_NEAR(sh9_irradiance(L, {0, -1, 0}).x, 2 * (0.25 - 0.5 + 5.0 / 16), 1e-4);
  // The visible disc carries E / solid angle.
  const Vec3 sun = normalize(sky.sun_direction);
  EXPECT_NEAR(sky_radiance(sky, sun, sun).x, 2 / sun_solid_angle(sky), 1e-2);
  EXPECT_EQ(sky_radiance(sky, sun, {1, 0, 0}).x, 0);
}

TEST(Shading, NormalisedBlinnPhongPeakAndDiffuse) {
  RenderSettings s;
  s.sky.zenith = s.sky.horizon = s.sky.ground = {1, 1, 1};
  s.sky.sun_irradiance = {1, 1, 1};
  s.sky.sun_direction = {0, 1, 0};
  s.specular = real(0.5);
  s.shininess = 20;
  const ShadingParams p = make_shading_params(s);
  // Mirror configuration: (n.h)^m = 1, so the highlight is k_s (m + 8) / (8 pi) E_sun.
  const Vec3 up{0, 1, 0};
  const Vec3 with_spec = shade_opaque(p, up, up, {0, 0, 0});
  EXPECT_NEAR(with_spec.x, 0.5 * 28 / (8 * kPiD), 1e-5);
  // Without the specular term: albedo / pi * E.
  ShadingParams q = p;
  q.specular = 0;
  const Vec3 diffuse = shade_opaque(q, up, up, {real(0.5), real(0.5), real(0.5)});
  EXPECT_NEAR(diffuse.x, 0.5 / kPiD * sh9_irradiance(p.sky_sh, up).x, 1e-5);
}

TEST(Shading, WoodTextureVariesAndStaysInRange) {
  std::set<int> tones;
  Random rng(4);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 c = wood_albedo(testing::uniform(rng, -3, 3), testing::uniform(rng, -3, 3), real(0.2));
    for (real v : {c.x, c.y, c.z}) {
      EXPECT_GE(v, 0);
      EXPECT_LE(v, 1);
    }
    EXPECT_GT(c.x, c.z);  // brown: more red than blue
    tones.insert(int(c.x * 50));
  }
  EXPECT_GT(tones.size(), 10u);
}

// One big cube under a constant sky, no sun, no floor: every face is lit alike, so each pixel is
// either the cube's colour (albedo * c) or the sky's (c).
TEST(Shading, DiffuseCubeUnderConstantSkyRendersUniformly) {
  const real c = real(0.8), albedo = real(0.5);
  RenderSettings s;
  s.width = 48;
  s.height = 32;
  s.spp = 2;
  s.sky.zenith = s.sky.horizon = s.sky.ground = {c, c, c};
  s.sky.sun_irradiance = {0, 0, 0};
  s.floor = false;
  s.exposure = 1;
  PrimitiveSet prims;
  prims.add_cube({0, 0, 0}, 1);
  const RenderScene scene = make_render_scene(prims, {{albedo, albedo, albedo}});
  const std::unique_ptr<Renderer> r = make_renderer(false);
  const uint8_t cube = linear_to_srgb8(albedo * c), sky = linear_to_srgb8(c);

  // Head-on, the front face fills the frame.
  Camera front;
  front.eye = {0, 0, 5};
  front.vfov_degrees = 15;
  const ImageRGB8 a = r->render_frame(scene, front, s).image;
  for (uint8_t v : a.rgb) ASSERT_EQ(v, cube);

  // From a corner: three faces and the sky around them (one sample per pixel, so no pixel mixes
  // the two).
  s.spp = 1;
  Camera corner;
  corner.eye = {3, 4, 5};
  const ImageRGB8 b = r->render_frame(scene, corner, s).image;
  int cube_pixels = 0, sky_pixels = 0;
  for (size_t i = 0; i < b.rgb.size(); i += 3) {
    const uint8_t v = b.rgb[i];
    EXPECT_EQ(b.rgb[i + 1], v);
    EXPECT_EQ(b.rgb[i + 2], v);
    if (v == cube)
      ++cube_pixels;
    else if (v == sky)
      ++sky_pixels;
    else
      ADD_FAILURE() << "pixel " << i / 3 << " has value " << int(v);
  }
  EXPECT_GT(cube_pixels, 100);
  EXPECT_GT(sky_pixels, 100);
}

}  // namespace
}  // namespace pd
