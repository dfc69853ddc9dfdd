// `render DIR`: frames of a run to PNG images, on the CPU renderer.
#include "host/app/render_frames.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "host/fragments/fragments_file.h"
#include "host/fragments/trimtope_file.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"
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

// --frames renders only the frames asked for (and makes no movie of them); a frame the run does
// not have is refused with the range it has.
TEST_F(RenderFramesTest, RendersOnlyTheChosenFrames) {
  RenderOptions o;
  o.dir = dir_.string();
  o.width = 32;
  o.height = 24;
  o.spp = 1;
  o.backend = "cpu";
  o.frames = {1};
  EXPECT_EQ(render_frames(o), 0);
  EXPECT_TRUE(fs::exists(path("render/frame_00001.png")));
  EXPECT_FALSE(fs::exists(path("render/frame_00000.png")));
  EXPECT_FALSE(fs::exists(path("render/movie.mp4")));
  o.frames = {0, 7};
  try {
    render_frames(o);
    FAIL() << "frame 7 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--frames 7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0 to 1"), std::string::npos) << e.what();
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

// A run directory of one Voronoi body (a box) with two frames: at rest, then rotated and moved
// as one fragment (fragments_00001.pfg).
class VoronoiRenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           ("perifrac_render_voronoi_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const ParticleGeometry g = voronoi_particles(box_mesh({0.4, 0.2, 0.3}), 0.05, 1, 100000, "box");
    trimtopes_ = rest_trimtopes(g);
    write_trimtopes_file((dir_ / kTrimtopesFileName).string(), trimtopes_);
    for (size_t i = 0; i < g.size(); ++i) {
      rest_.position.push_back({real(g.position[i][0]), real(g.position[i][1]), real(g.position[i][2])});
      rest_.volume.push_back(float(g.volume[i]));
      rest_.body.push_back(0);
      rest_.material.push_back(0);
    }
    write_rest_file((dir_ / kRestFileName).string(), rest_);
    fragment_.id = 0;
    fragment_.particles = int32_t(g.size());
    fragment_.rotation = Eigen::AngleAxisd(0.5, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
    fragment_.translation = Eigen::Vector3d(0.05, 0.1, -0.02);
    for (int f = 0; f < 2; ++f) {
      FrameData frame;
      frame.frame = f;
      for (size_t i = 0; i < g.size(); ++i) {
        const Eigen::Vector3d x(g.position[i][0], g.position[i][1], g.position[i][2]);
        const Eigen::Vector3d y = f == 0 ? x : fragment_.rotation * x + fragment_.translation;
        frame.position.push_back({real(y.x()), real(y.y()), real(y.z())});
      }
      frame.velocity.assign(g.size(), {0, 0, 0});
      frame.damage.assign(g.size(), 0.0f);
      frame.body.assign(g.size(), 0);
      frame.component.assign(g.size(), 0);
      write_frame_file((dir_ / frame_file_name(f, "pfr")).string(), frame);
      frames_.push_back(frame);
    }
    write_fragments_file((dir_ / fragments_file_name(1)).string(), 1, 0, 0, {fragment_});
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  RestData rest_;
  RestTrimtopes trimtopes_;
  Fragment fragment_;
  std::vector<FrameData> frames_;
};

TEST_F(VoronoiRenderTest, TrimtopesFollowTheirFragmentsTransform) {
  FragmentsFrame fr;
  fr.fragments = {fragment_};
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  frame_primitives(rest_, frames_[1], &prims, &albedo, &trimtopes_, &fr);
  ASSERT_EQ(size_t(prims.size()), rest_.size());
  for (size_t i = 0; i < rest_.size(); ++i) {
    ASSERT_EQ(prims.kind[i], kPrimTrimtope);
    // The placed site is where the frame has the particle (rest site moved by the fragment).
    const Vec3 s = prims.trim_site[size_t(prims.slot[i])];
    EXPECT_NEAR(s.x, frames_[1].position[i].x, 1e-5);
    EXPECT_NEAR(s.y, frames_[1].position[i].y, 1e-5);
    EXPECT_NEAR(s.z, frames_[1].position[i].z, 1e-5);
    // Its rotated planes keep it inside.
    for (int32_t k = prims.trim_plane_start[size_t(prims.slot[i])];
         k < prims.trim_plane_start[size_t(prims.slot[i]) + 1]; ++k)
      EXPECT_LT(dot(prims.trim_plane_normal[size_t(k)], s), prims.trim_plane_offset[size_t(k)]);
  }
  // Without fragments each trimtope moves with its particle (a translation).
  frame_primitives(rest_, frames_[0], &prims, &albedo, &trimtopes_, nullptr);
  const Vec3 s0 = prims.trim_site[size_t(prims.slot[3])];
  EXPECT_NEAR(s0.y, frames_[0].position[3].y, 1e-6);
}

TEST_F(VoronoiRenderTest, RendersTheRunWithTrimtopesOpaqueAndGlass) {
  for (const char* material : {"opaque", "glass"}) {
    RenderOptions o;
    o.dir = dir_.string();
    o.out = (dir_ / material).string();
    o.backend = "cpu";
    o.width = 48;
    o.height = 32;
    o.material = material;
    ASSERT_EQ(render_frames(o), 0);
    for (const char* name : {"frame_00000.png", "frame_00001.png"})
      EXPECT_GT(fs::file_size(dir_ / material / name), 100u) << material << " " << name;
  }
  RenderOptions bad;
  bad.dir = dir_.string();
  bad.material = "wood";
  EXPECT_THROW(render_frames(bad), std::invalid_argument);
}

}  // namespace
}  // namespace pd
