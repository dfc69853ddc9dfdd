// Scene set-up of every shape and particle kind: particles inside the body's solid with the
// solid's volume, mass = density x volume, and mesh problems reported as one-line SceneErrors.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tet_particles.h"
#include "host/geometry/tetgen.h"
#include "host/scene/scene_setup.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

constexpr double kPi = 3.14159265358979323846;

const std::string kHead =
    "[materials.glass]\ndensity = 2000\nbulk_modulus = 4.3e10\nstrain_limit = 0.001\n[[bodies]]\nmaterial = "
    "\"glass\"\n";

SetupResult setup(const std::string& body, const std::string& path = "test.toml", double scale = 1) {
  return setup_scene(parse_scene(kHead + body, path), SetupOptions(scale));
}

double total_volume(const ParticleSet& ps) {
  double v = 0;
  for (real x : ps.volume) v += x;
  return v;
}

TEST(SceneBodies, BoxGridIsUnchanged) {
  const SetupResult r = setup("size = [0.1, 0.05, 0.02]\nspacing = 0.01\ncenter = [1, 0, 0]\n");
  const ParticleSet& ps = r.input.particles;
  ASSERT_EQ(ps.size(), 100u);
  EXPECT_NEAR(ps.rest[0].x, 1 - 0.045, 1e-6);  // x fastest from the low corner
  EXPECT_NEAR(ps.mass[0], 2000 * 1e-6, 1e-9);
}

TEST(SceneBodies, SphereOfEveryKind) {
  const double volume = 4 * kPi / 3 * 0.001;  // radius 0.1
  for (const char* kind : {"grid", "voronoi", "tets"}) {
    SCOPED_TRACE(kind);
    if (std::string(kind) == "tets" && find_tetgen().empty()) continue;
    const SetupResult r =
        setup("shape = \"sphere\"\nradius = 0.1\nspacing = 0.01\ncenter = [0, 1, 0]\nparticles = \"" +
              std::string(kind) + "\"\n");
    const ParticleSet& ps = r.input.particles;
    ASSERT_GT(ps.size(), 1000u);
    EXPECT_NEAR(total_volume(ps), volume, 0.02 * volume);
    for (size_t i = 0; i < ps.size(); ++i) {
      ASSERT_LT(std::hypot(ps.rest[i].x, ps.rest[i].y - 1, ps.rest[i].z), 0.1 + 1e-6);
      ASSERT_NEAR(ps.mass[i], 2000 * ps.volume[i], 1e-6 * ps.mass[i]);
    }
  }
}

TEST(SceneBodies, VaseShellTorusCylinderPlate) {
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  EXPECT_GT(setup("shape = \"vase\"\nradius = 0.1\nheight = 0.3\nspacing = 0.006\nparticles = \"shell\"\n"
                  "shell_thickness = 0.006\nshell_layers = 3\n")
                .input.particles.size(),
            1000u);
  EXPECT_GT(setup("shape = \"vase\"\nradius = 0.1\nheight = 0.3\nwall = 0.01\nspacing = 0.005\n")
                .input.particles.size(),
            1000u);
  const SetupResult torus =
      setup("shape = \"torus\"\nradius = 0.2\ntube_radius = 0.05\nspacing = 0.01\nparticles = \"voronoi\"\n");
  EXPECT_NEAR(total_volume(torus.input.particles), 2 * kPi * kPi * 0.2 * 0.0025,
              0.01 * 2 * kPi * kPi * 0.2 * 0.0025);
  EXPECT_GT(setup("shape = \"cylinder\"\nradius = 0.05\nheight = 0.2\nspacing = 0.01\nparticles = \"tets\"\n")
                .input.particles.size(),
            100u);
  EXPECT_EQ(setup("shape = \"plate\"\nwidth = 0.1\ndepth = 0.2\nthickness = 0.01\nspacing = 0.01\n")
                .input.particles.size(),
            200u);
}

TEST(SceneBodies, ShellLayersFollowTheScaledSpacing) {
  EXPECT_EQ(scaled_shell_layers(4, 1), 4);
  EXPECT_EQ(scaled_shell_layers(4, 2), 3);    // 3 gaps at twice the spacing: 1.5, rounded to 2
  EXPECT_EQ(scaled_shell_layers(4, 10), 2);   // never fewer than one gap (outer + inner surface)
  EXPECT_EQ(scaled_shell_layers(3, 0.5), 5);  // a finer spacing: more layers through the wall
  EXPECT_EQ(scaled_shell_layers(2, 3), 2);
}

// --scale coarsens a shell body like any other: the spacing (and with it the surface mesh and
// the tet volume bound) grows by 1 / cbrt(scale), the layers through the wall follow, and the
// wall keeps its thickness, so the particle count falls about as scale and the volume stays.
TEST(SceneBodies, ShellCoarsensWithScale) {
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  const std::string vase =
      "shape = \"vase\"\nradius = 0.05\nheight = 0.15\nspacing = 0.002\nparticles = \"shell\"\n"
      "shell_thickness = 0.006\nshell_layers = 4\n";
  const SetupResult full = setup(vase);
  const SetupResult coarse = setup(vase, "test.toml", 0.125);  // spacing x 2: 2 layers, not 4
  const double n_full = double(full.input.particles.size()), n_coarse = double(coarse.input.particles.size());
  EXPECT_LT(n_coarse, 0.25 * n_full) << n_full << " particles at scale 1, " << n_coarse << " at 0.125";
  EXPECT_GT(n_coarse, 0.02 * n_full);
  // The same wall: the surfaces differ only by their facets.
  EXPECT_NEAR(total_volume(coarse.input.particles), total_volume(full.input.particles),
              0.03 * total_volume(full.input.particles));
  EXPECT_NEAR(coarse.materials[0].spacing / full.materials[0].spacing, 2, 0.5);
}

TEST(SceneBodies, TetKeepSurfaceOnlyWithTets) {
  const std::string sphere = "shape = \"sphere\"\nradius = 0.1\nspacing = 0.01\ntet_keep_surface = true\n";
  EXPECT_THROW(setup(sphere + "particles = \"grid\"\n"), SceneError);
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  const SetupResult r = setup(sphere + "particles = \"tets\"\n");
  const double volume = 4 * kPi / 3 * 0.001;
  EXPECT_GT(r.input.particles.size(), 1000u);
  EXPECT_NEAR(total_volume(r.input.particles), volume, 0.02 * volume);
}

TEST(SceneBodies, MeshRelativeToTheSceneFile) {
  test::ScratchDir dir("scene");
  write_obj(torus_mesh(1, 0.3, 0.1), dir.file("ring.obj"));
  const SetupResult r =
      setup("shape = \"mesh\"\nmesh = \"ring.obj\"\nscale = 0.1\nspacing = 0.005\n", dir.file("s.toml"));
  const double volume = 2 * kPi * kPi * 0.1 * 0.03 * 0.03;
  EXPECT_NEAR(total_volume(r.input.particles), volume, 0.05 * volume);
}

TEST(SceneBodies, MeshErrorsBecomeSceneErrors) {
  test::ScratchDir dir("scene-bad");
  TriMesh open = box_mesh({1, 1, 1});
  open.triangles.pop_back();
  open.triangles.pop_back();
  write_obj(open, dir.file("open.obj"));
  const std::string scene = dir.file("s.toml");
  try {
    setup("shape = \"mesh\"\nmesh = \"open.obj\"\nspacing = 0.1\n", scene);
    FAIL();
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(
        msg.rfind(scene + ": bodies[0].mesh: " + dir.file("open.obj") + ": the mesh is open: 1 hole", 0), 0u)
        << msg;
  }
  EXPECT_GT(setup("shape = \"mesh\"\nmesh = \"open.obj\"\nrepair = \"fill_holes\"\nspacing = 0.1\n", scene)
                .input.particles.size(),
            500u);
  try {
    setup("shape = \"sphere\"\nradius = 10\nspacing = 0.0001\n");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].particles: bodies[0]: the solid"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pd
