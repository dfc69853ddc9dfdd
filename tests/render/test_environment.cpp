// .hdr environments (render/environment.h): maps written here with stb_image_write, read back
// and projected onto SH (constant, step and linear maps against their analytic coefficients),
// the lookup's orientation, unusable files refused, and a diffuse sphere of tetrahedra under a
// constant map rendered uniform, with the map as the background.
#include "render/environment.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

#include "render/renderer.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace pd {
namespace {

namespace fs = std::filesystem;
const double kPiD = 3.14159265358979323846;
const double kY00 = 0.282094792, kY1 = 0.488602512;  // Y_00 and the l = 1 constant (sh.h)

class Environment : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("perifrac_env_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes a width x (width / 2) map whose texel (i, j) holds radiance(w) at its centre's
  // direction w (the layout of environment.h); returns its path.
  std::string write_map(const std::string& name, int width, const std::function<double(Vec3)>& radiance) {
    const int height = width / 2;
    std::vector<float> rgb;
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i) {
        const double theta = kPiD * (j + 0.5) / height, phi = 2 * kPiD * ((i + 0.5) / width - 0.5);
        const Vec3 w{real(std::sin(theta) * std::cos(phi)), real(std::cos(theta)),
                     real(std::sin(theta) * std::sin(phi))};
        const float v = float(radiance(w));
        rgb.insert(rgb.end(), {v, v, v});
      }
    const std::string path = (dir_ / name).string();
    EXPECT_NE(stbi_write_hdr(path.c_str(), width, height, 3, rgb.data()), 0);
    return path;
  }

  fs::path dir_;
};

TEST_F(Environment, ConstantMapHasOnlyTheDcTerm) {
  // 1.0 is exact in RGBE and each texel's Y_lm integral is exact: L_00 = sqrt(4 pi), the rest
  // zero, to round-off.
  const EnvironmentMap m = load_environment(write_map("constant.hdr", 128, [](Vec3) { return 1.0; }));
  EXPECT_EQ(m.width, 128);
  EXPECT_EQ(m.height, 64);
  EXPECT_NEAR(m.sh.c[0].x, std::sqrt(4 * kPiD), 1e-5);
  for (int k = 1; k < 9; ++k) EXPECT_NEAR(m.sh.c[k].y, 0, 1e-5) << k;
}

TEST_F(Environment, StepMapGivesTheHemisphereCoefficients) {
  // 2 above the horizon, 0.5 below (both exact in RGBE, the horizon a texel boundary):
  // L_00 = Y_00 2 pi (2 + 0.5), L_1-1 (the y term) = Y_1 (2 pi - 0.5 pi), the rest zero by
  // symmetry; the map is piecewise constant on texels, so exact to round-off.
  const EnvironmentMap m =
      load_environment(write_map("step.hdr", 128, [](Vec3 w) { return w.y > 0 ? 2.0 : 0.5; }));
  EXPECT_NEAR(m.sh.c[0].x, kY00 * 2 * kPiD * 2.5, 1e-5);
  EXPECT_NEAR(m.sh.c[1].x, kY1 * 1.5 * kPiD, 1e-5);
  for (int k = 2; k < 9; ++k) EXPECT_NEAR(m.sh.c[k].x, 0, 1e-5) << k;
}

TEST_F(Environment, LinearMapAlongXGivesTheL11Term) {
  // Radiance 1 + 0.5 x: L_00 = sqrt(4 pi), L_11 (the x term) = 0.5 Y_1 4 pi / 3, the rest zero.
  // RGBE keeps 8 mantissa bits: each texel is off by at most 2^-7 of its value (<= 1.5), so each
  // coefficient by at most 2^-7 1.5 times the integral of |Y_lm|, which is <= sqrt(4 pi).
  const EnvironmentMap m =
      load_environment(write_map("linear.hdr", 256, [](Vec3 w) { return 1 + 0.5 * w.x; }));
  const double rgbe = std::ldexp(1.0, -7) * 1.5 * std::sqrt(4 * kPiD);
  EXPECT_NEAR(m.sh.c[0].x, std::sqrt(4 * kPiD), rgbe);
  EXPECT_NEAR(m.sh.c[3].x, 0.5 * kY1 * 4 * kPiD / 3, rgbe);
  for (int k : {1, 2, 4, 5, 6, 7, 8}) EXPECT_NEAR(m.sh.c[k].x, 0, rgbe) << k;
  // The lookup: +x sees 1.5, -x 0.5, +-z and +-y 1 (RGBE and bilinear interpolation aside).
  const EnvironmentView v = m.view();
  const std::map<std::array<int, 3>, double> expect = {{{1, 0, 0}, 1.5}, {{-1, 0, 0}, 0.5},
                                                       {{0, 0, 1}, 1.0}, {{0, 0, -1}, 1.0},
                                                       {{0, 1, 0}, 1.0}, {{0, -1, 0}, 1.0}};
  for (const auto& [d, value] : expect)
    EXPECT_NEAR(environment_radiance(v, {real(d[0]), real(d[1]), real(d[2])}).x, value, 0.015)
        << d[0] << " " << d[1] << " " << d[2];
}

TEST_F(Environment, UnusableFilesAreRefusedNamingTheFile) {
  auto message = [](const std::string& path) {
    try {
      load_environment(path);
    } catch (const EnvironmentError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = (dir_ / "missing.hdr").string();
  EXPECT_NE(message(missing).find("missing.hdr': No such file"), std::string::npos) << message(missing);
  const std::string text = (dir_ / "text.hdr").string();
  std::ofstream(text) << "not an image\n";
  EXPECT_NE(message(text).find("not a Radiance .hdr file"), std::string::npos) << message(text);
  EXPECT_NE(message(text).find("allowed: a Radiance .hdr"), std::string::npos);
  const std::string square = (dir_ / "square.hdr").string();
  const std::vector<float> pixels(3 * 16 * 16, 1.0f);
  ASSERT_NE(stbi_write_hdr(square.c_str(), 16, 16, 3, pixels.data()), 0);
  EXPECT_NE(message(square).find("16 x 16 texels"), std::string::npos) << message(square);
  // A map cut short (a copy that stopped, a download that failed) is refused, not drawn black
  // where its texels are missing; the whole file loads.
  const std::string whole = write_map("whole.hdr", 64, [](Vec3) { return 1.0; });
  EXPECT_EQ(message(whole), "no error");
  const std::uintmax_t size = fs::file_size(whole);
  for (const auto cut : {size - 1, size / 2, std::uintmax_t{20}}) {  // 20 bytes: within the header
    const std::string cut_path = (dir_ / ("cut" + std::to_string(cut) + ".hdr")).string();
    fs::copy_file(whole, cut_path);
    fs::resize_file(cut_path, cut);
    const std::string expected =
        cut > 20 ? "truncated: the file ends before its 64 x 32 texels do" : "cut20.hdr': truncated (allowed";
    EXPECT_NE(message(cut_path).find(expected), std::string::npos) << message(cut_path);
  }
}

// The unit sphere as 320 tetrahedra: an icosahedron subdivided twice, projected onto the sphere,
// each triangle coned to the centre.
PrimitiveSet tet_sphere() {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                          {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                          {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  auto unit = [](std::array<double, 3> p) {
    const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::array<double, 3>{p[0] / l, p[1] / l, p[2] / l};
  };
  for (auto& p : v) p = unit(p);
  for (int level = 0; level < 2; ++level) {
    std::vector<std::array<int, 3>> finer;
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(unit({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      return mid[key] = int(v.size() - 1);
    };
    for (const auto& t : f) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      finer.insert(finer.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
    }
    f = finer;
  }
  PrimitiveSet s;
  auto at = [&](int k) { return Vec3{real(v[k][0]), real(v[k][1]), real(v[k][2])}; };
  for (const auto& t : f) s.add_tet({0, 0, 0}, at(t[0]), at(t[1]), at(t[2]));
  return s;
}

// Under a constant environment the SH irradiance is the same for every normal, so a diffuse
// sphere is one flat colour, albedo * c, and the background the map's c (no sun, no highlight).
TEST_F(Environment, DiffuseSphereUnderAConstantMapRendersUniform) {
  const real c = real(0.5), albedo = real(0.6);
  RenderSettings s;
  s.width = 64;
  s.height = 48;
  s.spp = 1;  // pixel centres: no pixel mixes sphere and background
  s.floor = false;
  s.exposure = 1;
  s.environment =
      std::make_shared<EnvironmentMap>(load_environment(write_map("c.hdr", 64, [&](Vec3) { return c; })));
  const PrimitiveSet prims = tet_sphere();
  ASSERT_EQ(prims.size(), 320);
  const RenderScene scene = make_render_scene(prims, std::vector<Vec3>(320, {albedo, albedo, albedo}));
  Camera camera;
  camera.eye = {real(0.3), real(0.4), 5};  // off-axis, so many facets face the camera
  camera.vfov_degrees = 30;
  const ImageRGB8 image = make_renderer(false)->render_frame(scene, camera, s).image;
  const uint8_t sphere = linear_to_srgb8(albedo * c), background = linear_to_srgb8(c);
  ASSERT_NE(sphere, background);
  int sphere_pixels = 0, background_pixels = 0;
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    const uint8_t v = image.rgb[i];
    EXPECT_EQ(image.rgb[i + 1], v);
    EXPECT_EQ(image.rgb[i + 2], v);
    if (v == sphere)
      ++sphere_pixels;
    else if (v == background)
      ++background_pixels;
    else
      ADD_FAILURE() << "pixel " << i / 3 << " has value " << int(v);
  }
  // The sphere's disc: angular radius asin(1 / 5.025) of the 15-degree half field, 48 rows high:
  // radius ~ 0.2 / tan(15 deg) * 24 = 18 pixels, about 1020 pixels (facets make it a little less).
  EXPECT_GT(sphere_pixels, 900);
  EXPECT_LT(sphere_pixels, 1100);
  EXPECT_GT(background_pixels, 1500);
}

}  // namespace
}  // namespace pd
