// `render DIR`: frames of a run to PNG images, on the CPU renderer.
#include "render/render_frames.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/io/atomic_file.h"
#include "host/io/frame_file.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

// A run directory with a 6 x 4 x 5 lattice of two bodies and two frames, removed afterwards.
class RenderFramesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           ("perifrac_render_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const real lambda = real(0.01);
    for (int k = 0; k < 5; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 6; ++i) {
          rest_.position.push_back({i * lambda, j * lambda + real(0.05), k * lambda});
          rest_.volume.push_back(float(lambda * lambda * lambda));
          rest_.body.push_back(i < 3 ? 0 : 1);
          rest_.material.push_back(0);
        }
    write_rest_file(path(kRestFileName), rest_);
    for (int f = 0; f < 2; ++f) {
      FrameData frame;
      frame.frame = f;
      frame.position = rest_.position;
      for (Vec3& p : frame.position) p.y -= real(0.01) * real(f);
      frame.velocity.assign(rest_.size(), {0, 0, 0});
      frame.damage.assign(rest_.size(), f == 0 ? 0.0f : 0.5f);
      frame.body = rest_.body;
      write_frame_file(path(frame_file_name(f, "pfr")), frame);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
  RestData rest_;
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(RenderFramesTest, WritesOnePngPerFrame) {
  RenderOptions o;
  o.dir = dir_.string();
  o.backend = "cpu";
  o.width = 40;
  o.height = 30;
  o.spp = 2;
  ASSERT_EQ(render_frames(o), 0);
  for (const char* name : {"frame_00000.png", "frame_00001.png"}) {
    const std::string png = read_all((dir_ / "render" / name).string());
    ASSERT_GT(png.size(), 24u) << name;
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(uint8_t(png[19]), 40);  // IHDR width, low byte
    EXPECT_EQ(uint8_t(png[23]), 30);  // IHDR height, low byte
  }
}

TEST_F(RenderFramesTest, FramedCameraSeesTheBlockInTheMiddle) {
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  frame_primitives(rest_, read_frame_file(path("frame_00000.pfr")), &prims, &albedo);
  ASSERT_EQ(prims.size(), 120);
  EXPECT_NEAR(prims.cube_half[0], 0.005, 1e-6);  // half of cbrt(volume)
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  s.floor = false;
  const Camera camera = frame_box(cube_bounds(rest_.position, rest_.volume), s.width, s.height);
  const RenderResult r = make_renderer(false)->render_frame(make_render_scene(prims, albedo), camera, s);
  EXPECT_EQ(r.rays, 40 * 30);
  // The centre ray hits the block, a corner ray misses it.
  const uint8_t* centre = r.image.pixel(20, 15);
  const uint8_t* corner = r.image.pixel(0, 0);
  EXPECT_NE(std::vector<uint8_t>(centre, centre + 3), std::vector<uint8_t>(corner, corner + 3));
}

TEST(ParticleColor, BodiesDifferAndDamageTintsRed) {
  const Vec3 a = particle_color(0, 0), b = particle_color(1, 0), hurt = particle_color(0, 1);
  EXPECT_NE(a.x, b.x);
  EXPECT_GT(hurt.x - hurt.z, a.x - a.z);
  const Vec3 negative = particle_color(-1, 0);  // any body id maps into the palette
  EXPECT_GE(negative.x, 0);
}

TEST_F(RenderFramesTest, RejectsMismatchedFramesAndMissingInputs) {
  FrameData short_frame = read_frame_file(path("frame_00000.pfr"));
  short_frame.position.pop_back();
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  EXPECT_THROW(frame_primitives(rest_, short_frame, &prims, &albedo), std::invalid_argument);
  RenderOptions o;
  o.dir = (dir_ / "missing").string();
  o.backend = "cpu";
  EXPECT_THROW(render_frames(o), IoError);
  o.dir = dir_.string();
  o.spp = 0;
  EXPECT_THROW(render_frames(o), std::invalid_argument);
}

}  // namespace
}  // namespace pd
