// `render DIR`: frames of a run to PNG images, on the CPU renderer.
#include "host/app/render_frames.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Geometry>

#include "host/fragments/crack_mesh_file.h"
#include "host/fragments/fragments_file.h"
#include "host/fragments/trimtope_file.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"
#include "host/io/atomic_file.h"
#include "host/io/collider_file.h"
#include "host/io/frame_file.h"

#include "tests/support/stb_png.h"

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

// render_frames's refusal of `o` (std::invalid_argument, the user's mistake), or "no refusal".
std::string refusal(const RenderOptions& o) {
  try {
    render_frames(o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no refusal";
}

// A run's manifest and journal (run_folder.h) as a run leaves them: frames 0 to `written`
// complete, the files named in the journal.
void write_run_records(const fs::path& dir, int64_t written, const std::vector<std::string>& files) {
  std::ofstream(dir / kManifestFileName) << "perifrac test\nscene_path /nowhere.toml\nscene_hash 1\nscale 1\n"
                                            "overrides 0\nframes_written "
                                         << written << "\n";
  std::ofstream journal(dir / kJournalFileName);
  for (const std::string& f : files) journal << "-1 " << f << "\n";
}

// The frame a killed run was writing is left out, said so; a file the run wrote that is gone is
// an error naming it, not a frame drawn without it.
TEST_F(RenderFramesTest, UsesTheCompleteFramesAndRefusesMissingFilesTheRunWrote) {
  RenderOptions o;
  o.dir = dir_.string();
  o.backend = "cpu";
  o.width = o.height = 16;
  o.spp = 1;
  o.movie = false;
  write_run_records(dir_, 0, {"rest.pfr", "frame_00000.pfr", "frame_00001.pfr"});
  ASSERT_EQ(render_frames(o), 0);
  EXPECT_TRUE(fs::exists(path("render/frame_00000.png")));
  EXPECT_FALSE(fs::exists(path("render/frame_00001.png")));  // (past frames_written)
  o.frames = {1};
  EXPECT_THROW(render_frames(o), std::invalid_argument);
  o.frames.clear();

  // Frame 1 complete but its file gone; then a set-up file gone.
  write_run_records(dir_, 1, {"rest.pfr", "frame_00000.pfr", "frame_00001.pfr"});
  fs::remove(path("frame_00001.pfr"));
  try {
    render_frames(o);
    FAIL() << "a missing frame was passed over";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_00001.pfr"), std::string::npos) << e.what();
  }
  write_run_records(dir_, 0, {"rest.pfr", "frame_00000.pfr", kTrimtopesFileName, colliders_file_name(0)});
  for (const std::string& gone : {std::string(kTrimtopesFileName), colliders_file_name(0)}) {
    try {
      render_frames(o);
      FAIL() << gone << " missing was passed over";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(gone), std::string::npos) << e.what();
    }
    write_run_records(dir_, 0, {"rest.pfr", "frame_00000.pfr", colliders_file_name(0)});
  }
}

// A run made with output.binary = false wrote no .pfr frames: said so, not "no run here".
TEST_F(RenderFramesTest, ARunWithoutBinaryFramesIsNamedAsSuch) {
  fs::remove(path("frame_00000.pfr"));
  fs::remove(path("frame_00001.pfr"));
  write_run_records(dir_, 1, {"frame_00000.vtu", "frame_00001.vtu"});
  RenderOptions o;
  o.dir = dir_.string();
  o.backend = "cpu";
  EXPECT_NE(refusal(o).find("output.binary = false"), std::string::npos) << refusal(o);
}

// Repeated or unordered --frames render each frame once, in order; an --out that is a file is
// the user's mistake.
TEST_F(RenderFramesTest, FramesOnceInOrderAndOutMustBeAFolder) {
  std::string note;
  const std::vector<std::string> chosen = select_frame_files(dir_.string(), {}, {1, 0, 1}, &note);
  ASSERT_EQ(chosen.size(), 2u);
  EXPECT_EQ(fs::path(chosen[0]).filename(), "frame_00000.pfr");
  EXPECT_EQ(fs::path(chosen[1]).filename(), "frame_00001.pfr");
  EXPECT_TRUE(note.empty());
  RenderOptions o;
  o.dir = dir_.string();
  o.backend = "cpu";
  o.out = path("frame_00000.pfr");
  EXPECT_NE(refusal(o).find("is a file, not a folder"), std::string::npos) << refusal(o);
}

// A camera straight above its target renders (the image's up is -z), one too far out is refused
// naming the option.
TEST_F(RenderFramesTest, TopDownCameraRendersAndAFarOneIsRefused) {
  RenderOptions o;
  o.dir = dir_.string();
  o.backend = "cpu";
  o.width = o.height = 16;
  o.spp = 1;
  o.movie = false;
  o.look_at = Vec3{real(0.03), real(0.05), real(0.02)};
  o.eye = Vec3{real(0.03), real(1), real(0.02)};
  EXPECT_EQ(render_frames(o), 0);
  o.eye = Vec3{real(1e30), real(1e30), real(1e30)};
  EXPECT_NE(refusal(o).find("eye 1e+30"), std::string::npos) << refusal(o);
}

// SIGINT while `perifrac render` works: it stops after the image in progress, says how many are
// done, exits with 130 and leaves no half-written image.
TEST_F(RenderFramesTest, AnInterruptStopsBetweenFramesWithTheImagesComplete) {
  for (int f = 2; f < 40; ++f) {  // (more frames than the render finishes before the signal)
    FrameData frame = read_frame_file(path("frame_00001.pfr"));
    frame.frame = f;
    write_frame_file(path(frame_file_name(f, "pfr")), frame);
  }
  const std::string log = path("render.log");
  const pid_t pid = fork();
  if (pid == 0) {
    setenv("OMP_NUM_THREADS", "1", 1);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execl(PERIFRAC_BINARY, PERIFRAC_BINARY, "render", dir_.c_str(), "--backend", "cpu", "--width", "400",
          "--height", "300", "--spp", "4", "--no-movie", static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int i = 0; i < 3000 && !fs::exists(path("render/frame_00000.png")); ++i) ::usleep(10000);
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << read_all(log);
  EXPECT_EQ(WEXITSTATUS(status), 130) << read_all(log);
  EXPECT_NE(read_all(log).find("interrupted after"), std::string::npos) << read_all(log);
  EXPECT_FALSE(fs::exists(path("render/frame_00039.png")));
  for (const auto& e : fs::directory_iterator(path("render")))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
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
  // A folder that is not there, or holds no run: the user's mistake (exit 2), said so.
  RenderOptions o;
  o.backend = "cpu";
  auto refusal = [&](const std::string& dir) {
    o.dir = dir;
    try {
      render_frames(o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no refusal");
  };
  EXPECT_NE(refusal((dir_ / "missing").string()).find("is not there"), std::string::npos);
  std::filesystem::create_directories(dir_ / "empty");
  EXPECT_NE(refusal((dir_ / "empty").string()).find("holds no complete frame_*.pfr nor rest.pfr"),
            std::string::npos);
  EXPECT_NE(refusal(path("frame_00000.pfr")).find("is not a folder"), std::string::npos);
  o.dir = dir_.string();
  o.spp = 0;
  EXPECT_THROW(render_frames(o), std::invalid_argument);
}

// The closed surface of body 0's cubes in frame f (the lattice's cubes i < 3), quads as two
// triangles counter-clockwise from outside, each owned by its cube's particle: the crack mesh a run
// would write for an unbroken body 0.
CrackSurface body0_surface(const FrameData& frame, real lambda) {
  CrackSurface s;
  std::map<std::array<int, 3>, int32_t> corner;  // lattice corner (doubled coordinates) -> vertex
  const Vec3 origin = frame.position[0];
  auto vertex = [&](std::array<int, 3> c) {
    const auto [it, added] = corner.emplace(c, int32_t(s.vertices.size()));
    if (added)
      s.vertices.push_back(
          {origin.x + 0.5 * lambda * c[0], origin.y + 0.5 * lambda * c[1], origin.z + 0.5 * lambda * c[2]});
    return it->second;
  };
  const int n[3] = {3, 4, 5};
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i)
        for (int a = 0; a < 3; ++a)
          for (int side = -1; side <= 1; side += 2) {
            const int at[3] = {i, j, k};
            if (at[a] + side >= 0 && at[a] + side < n[a]) continue;  // a neighbour of body 0 there
            // The face's corners counter-clockwise seen from outside: (b, c) = the next two axes.
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            int32_t q[4];
            const int sb[4] = {-1, 1, 1, -1}, sc[4] = {-1, -1, 1, 1};
            for (int m = 0; m < 4; ++m) {
              std::array<int, 3> x{2 * i, 2 * j, 2 * k};
              x[size_t(a)] += side;
              x[size_t(b)] += side > 0 ? sb[m] : sb[3 - m];
              x[size_t(c)] += side > 0 ? sc[m] : sc[3 - m];
              q[m] = vertex(x);
            }
            const int32_t owner = (k * 4 + j) * 6 + i;
            s.triangles.push_back({q[0], q[1], q[2]});
            s.triangles.push_back({q[0], q[2], q[3]});
            s.crack.insert(s.crack.end(), {0, 0});
            s.particle.insert(s.particle.end(), {owner, owner});
          }
  return s;
}

using testing_png::Png;
using testing_png::read_png;

// Pixels whose colour differs by more than `tol` in a channel.
int differing_pixels(const Png& a, const Png& b, int tol) {
  int count = 0;
  for (size_t i = 0; i + 2 < a.rgb.size(); i += 3)
    for (size_t c = 0; c < 3; ++c)
      if (std::abs(int(a.rgb[i + c]) - int(b.rgb[i + c])) > tol) {
        ++count;
        break;
      }
  return count;
}

// --surface mesh draws body 0 from its crack mesh and body 1 from its cubes: the mesh is body 0's
// cube surface, so the image is the elements' one but for round-off at edges, in both the
// bodies' looks and the damage colours. The mesh moved shows where body 0 is and nowhere else; a
// frame without its crack mesh, or a mesh without owners, is an error naming the file.
TEST_F(RenderFramesTest, SurfaceMeshDrawsTheCoveredBodiesFromTheirMesh) {
  const real lambda = real(0.01);
  for (int f = 0; f < 2; ++f)
    write_crack_ply(path(crack_mesh_file_name(f, "ply")),
                    body0_surface(read_frame_file(path(frame_file_name(f, "pfr"))), lambda), "test");
  RenderOptions o;
  o.dir = dir_.string();
  o.backend = "cpu";
  o.width = 80;
  o.height = 60;
  o.spp = 1;
  o.movie = false;
  o.damage_colors = true;
  // From the front, looking along -z at the block's middle: body 0 (x < 0.025) on the left half.
  o.eye = Vec3{real(0.025), real(0.065), real(0.15)};
  o.look_at = Vec3{real(0.025), real(0.065), real(0.02)};
  o.out = path("elements");
  ASSERT_EQ(render_frames(o), 0);
  o.surface = "mesh";
  o.out = path("mesh");
  ASSERT_EQ(render_frames(o), 0);
  for (const char* name : {"frame_00000.png", "frame_00001.png"}) {
    SCOPED_TRACE(name);
    const Png elements = read_png(path("elements/") + name), mesh = read_png(path("mesh/") + name);
    ASSERT_EQ(mesh.width, 80);
    ASSERT_EQ(mesh.rgb.size(), elements.rgb.size());
    EXPECT_LE(differing_pixels(elements, mesh, 2), 80 * 60 / 100);
  }

  // Body 0's mesh lifted by two cubes: the image changes, and only on the left half, where body 0
  // and its lifted copy are seen.
  CrackSurface lifted = body0_surface(read_frame_file(path("frame_00000.pfr")), lambda);
  for (Vec3d& v : lifted.vertices) v[1] += 2 * lambda;
  write_crack_ply(path("crack_mesh_00000.ply"), lifted, "test");
  o.out = path("lifted");  // all frames: the last one sets the floor
  ASSERT_EQ(render_frames(o), 0);
  const Png base = read_png(path("elements/frame_00000.png")),
            moved = read_png(path("lifted/frame_00000.png"));
  ASSERT_EQ(moved.rgb.size(), base.rgb.size());
  EXPECT_GT(differing_pixels(base, moved, 2), 80 * 60 / 50);
  int right = 0;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x) {
      const size_t i = 3 * size_t(y * 80 + x);
      bool differs = false;
      for (size_t c = 0; c < 3; ++c) differs |= std::abs(int(base.rgb[i + c]) - int(moved.rgb[i + c])) > 2;
      right += differs && x > 48;
    }
  EXPECT_LE(right, 80 * 60 / 200) << "body 1 (drawn as cubes) changed";

  // A frame without its crack mesh; a mesh that does not name its faces' particles.
  fs::remove(path("crack_mesh_00001.ply"));
  o.frames = {1};
  try {
    render_frames(o);
    FAIL() << "a frame without a crack mesh was rendered";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("crack_mesh_00001.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("must write crack meshes"), std::string::npos) << e.what();
  }
  lifted.particle.clear();
  write_crack_ply(path("crack_mesh_00001.ply"), lifted, "test");
  EXPECT_THROW(render_frames(o), std::invalid_argument);
  o.surface = "faces";
  EXPECT_THROW(check_render_options(o), std::invalid_argument);
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
