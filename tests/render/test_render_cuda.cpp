// The CUDA renderer against the CPU renderer (skipped without a usable GPU; then asking for the
// GPU renderer must fail cleanly): the same frame from both agrees to PSNR >= 40 dB for opaque
// cubes, tets and turned cubes, a glass block, and Voronoi trimtopes opaque and glass.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <memory>

#include "cuda/engine/engine.h"
#include "host/fragments/voronoi_trimtopes.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"
#include "render/renderer.h"
#include "render/tet_lattice.h"
#include "tests/render/render_scenes.h"

namespace pd {
namespace {

// Renders `scene` on both backends and compares. Fused multiply-adds on the device move some
// values by an ulp, which may change a silhouette pixel or an 8-bit level: 40 dB allows an MSE of
// 6.5 levels squared, e.g. one channel in 1600 off by 100 levels.
void expect_same_image(const RenderScene& scene, const Camera& camera, const RenderSettings& s,
                       const char* what) {
  const ImageRGB8 cpu = make_renderer(false)->render_frame(scene, camera, s).image;
  const RenderResult gpu = make_renderer(true)->render_frame(scene, camera, s);
  ASSERT_EQ(gpu.image.rgb.size(), cpu.rgb.size()) << what;
  const double db = psnr(cpu, gpu.image);
  EXPECT_GE(db, 40) << what;
  EXPECT_GT(gpu.seconds, 0) << what;
  std::printf("%s: CPU vs GPU PSNR %.1f dB\n", what, db);
}

bool gpu_or_skip() {
  std::string why;
  if (cuda_device_available(&why)) return true;
  EXPECT_THROW(make_renderer(true), std::runtime_error);
  std::printf("skipped: %s\n", why.c_str());
  return false;
}

RenderSettings settings() {
  RenderSettings s;
  s.width = 320;
  s.height = 200;
  s.spp = 2;
  return s;
}

TEST(CudaRenderer, OpaqueCubesTetsAndTurnedCubesMatchTheCpu) {
  if (!gpu_or_skip()) GTEST_SKIP();
  // Cubes, tets and turned cubes over a lattice block, floor, sun and sky: every opaque path.
  PrimitiveSet prims = testing::random_scene(9, 400, 400);
  Random rng(4);
  testing::add_random_oriented_cubes(prims, rng, 300);
  const PrimitiveSet block = testing::lattice_scene(20, 6, 20, real(0.1));
  for (int32_t i = 0; i < block.size(); ++i)
    prims.add_cube(block.cube_center[size_t(i)] - Vec3{1, real(1.6), 1}, block.cube_half[size_t(i)]);
  std::vector<Vec3> albedo;
  for (int32_t i = 0; i < prims.size(); ++i) albedo.push_back(testing::uniform_point(rng, 0.1, 0.9));
  const RenderScene scene = make_render_scene(prims, albedo);
  RenderSettings s = settings();
  s.floor_y = real(-1.7);
  expect_same_image(scene, frame_box(scene.tree.bounds, s.width, s.height), s,
                    "opaque cubes, tets, turned cubes");
}

// A big frame with a stop question is drawn in parts (RenderSettings::stop): on the GPU, launches
// over stretches of the tiles, the same bits as one launch over all of them.
TEST(CudaRenderer, AFrameInPartsIsTheFrameInOneLaunch) {
  if (!gpu_or_skip()) GTEST_SKIP();
  const PrimitiveSet prims = testing::random_scene(9, 400, 400);
  const RenderScene scene =
      make_render_scene(prims, std::vector<Vec3>(size_t(prims.size()), Vec3{0.6, 0.4, 0.3}));
  RenderSettings s;
  s.width = 1024;
  s.height = 1024;
  s.spp = 32;  // 2^20 pixels and 2^25 samples: four parts
  const Camera camera = frame_box(scene.tree.bounds, s.width, s.height);
  const std::unique_ptr<Renderer> gpu = make_renderer(true);
  const RenderResult whole = gpu->render_frame(scene, camera, s);
  int asked = 0;
  s.stop = [&asked] { return ++asked < 0; };
  const RenderResult parts = gpu->render_frame(scene, camera, s);
  EXPECT_EQ(asked, 3);
  EXPECT_FALSE(parts.stopped);
  EXPECT_TRUE(parts.image.rgb == whole.image.rgb);
}

TEST(CudaRenderer, GlassBlockMatchesTheCpu) {
  if (!gpu_or_skip()) GTEST_SKIP();
  // A glass block of touching cubes in front of opaque tets: refraction, Fresnel reflection and
  // the union walk.
  PrimitiveSet prims = testing::lattice_scene(12, 4, 12, real(0.1));
  const int32_t glass = prims.size();
  const PrimitiveSet behind = testing::random_scene(12, 0, 300);
  for (size_t k = 0; k < behind.tet_vertex.size(); k += 4) {
    const Vec3 shift{real(0.6), real(0.2), real(-1.6)};
    prims.add_tet(behind.tet_vertex[k] + shift, behind.tet_vertex[k + 1] + shift,
                  behind.tet_vertex[k + 2] + shift, behind.tet_vertex[k + 3] + shift);
  }
  std::vector<uint8_t> material(size_t(prims.size()), kMaterialOpaque);
  std::fill(material.begin(), material.begin() + glass, uint8_t(kMaterialGlass));
  const RenderScene scene = make_render_scene(
      prims, std::vector<Vec3>(size_t(prims.size()), {real(0.8), real(0.5), real(0.3)}), material);
  RenderSettings s = settings();
  s.floor_y = real(-0.05);
  Camera camera;
  camera.eye = {real(0.6), real(1.2), real(2.4)};
  camera.look_at = {real(0.6), real(0.1), real(0.4)};
  expect_same_image(scene, camera, s, "glass block");
}

// Pixels of `a` and `b` whose channels differ by more than `levels` anywhere.
int64_t differing_pixels(const ImageRGB8& a, const ImageRGB8& b, int levels) {
  int64_t n = 0;
  for (size_t p = 0; p + 2 < a.rgb.size(); p += 3) {
    bool differs = false;
    for (size_t c = 0; c < 3; ++c) differs |= std::abs(int(a.rgb[p + c]) - int(b.rgb[p + c])) > levels;
    n += differs;
  }
  return n;
}

// A jittered block of tetrahedra, one colour: leaving the hidden ones out of the kd-tree
// (hidden_tets.h) gives the image of the whole set on each backend, so no ray slips through the
// skin with the GPU's face crossings either; and the GPU image matches the CPU's.
TEST(CudaRenderer, HiddenTetrahedraLeaveTheImageAsItWas) {
  PrimitiveSet prims;
  add_tet_lattice(&prims, 14, 6, 12, 0.1, 0.2);
  const std::vector<Vec3> albedo(size_t(prims.size()), {real(0.7), real(0.6), real(0.5)});
  const RenderScene culled = make_render_scene(prims, albedo);
  const RenderScene all = make_render_scene(prims, albedo, {}, {}, HiddenElements::kKeep);
  ASSERT_GT(culled.hidden, prims.size() / 5);
  RenderSettings s = settings();
  Camera camera;
  camera.eye = {real(1.1), real(1.4), real(1.6)};
  camera.look_at = {0, real(0.3), 0};
  const bool gpu = cuda_device_available(nullptr);
  for (bool on_gpu : {false, true}) {
    if (on_gpu && !gpu) continue;
    const std::unique_ptr<Renderer> r = make_renderer(on_gpu);
    const ImageRGB8 a = r->render_frame(culled, camera, s).image, b = r->render_frame(all, camera, s).image;
    const int64_t differ = differing_pixels(a, b, 2);
    std::printf("%s: %lld of %d pixels differ by more than 2 levels with the hidden tetrahedra left out\n",
                on_gpu ? "GPU" : "CPU", (long long)differ, s.width * s.height);
    EXPECT_EQ(differ, 0) << (on_gpu ? "GPU" : "CPU");
  }
  if (gpu) expect_same_image(culled, camera, s, "tetrahedra, hidden ones left out");
}

TEST(CudaRenderer, VoronoiTrimtopesMatchTheCpuOpaqueAndGlass) {
  if (!gpu_or_skip()) GTEST_SKIP();
  const ParticleGeometry g = voronoi_particles(sphere_mesh(0.5, 0.08), 0.06, 7, 1000000, "sphere");
  const RestTrimtopes rest = rest_trimtopes(g);
  PrimitiveSet prims;
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  for (size_t i = 0; i < rest.size(); ++i)
    add_placed_trimtope(&prims, rest, i, r, Eigen::Vector3d(0, 0.5, 0));
  const std::vector<Vec3> albedo(size_t(prims.size()), {real(0.7), real(0.3), real(0.2)});
  RenderSettings s = settings();
  s.floor_y = 0;
  Camera camera;
  camera.eye = {real(1.2), real(1.3), real(1.8)};
  camera.look_at = {0, real(0.5), 0};
  expect_same_image(make_render_scene(prims, albedo), camera, s, "trimtopes opaque");
  expect_same_image(make_render_scene(prims, albedo, std::vector<uint8_t>(albedo.size(), kMaterialGlass)),
                    camera, s, "trimtopes glass");
}

}  // namespace
}  // namespace pd
