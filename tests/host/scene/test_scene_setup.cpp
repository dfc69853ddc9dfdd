// Scene set-up (host/scene/scene_setup.h): colliders as the engine takes them, their push in the
// stable time step, and a free collider's mass and inertia.
#include "host/scene/scene_setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/scene/scene.h"

namespace pd {
namespace {

const std::string kWall = R"(
[simulation]
dt = 1e-7
[materials.brick]
model = "bond_based"
density = 1900
bulk_modulus = 5e9
strain_limit = 1e-3
[[bodies]]
shape = "box"
center = [0, 0.05, 0]
size = [0.1, 0.1, 0.1]
spacing = 0.01
material = "brick"
)";

SetupResult set_up(const std::string& extra) {
  return setup_scene(parse_scene(kWall + extra, "scene.toml"), SetupOptions(1.0));
}

TEST(SceneSetup, PenaltyCollidersShortenTheStableStepAndTheIndentLawDoesNot) {
  const double bonds = set_up("").critical_dt;
  const SetupResult ground = set_up("[[colliders]]\nshape = \"plane\"\ncenter = [0, 0, 0]\n");
  // Default K: the brick's Young's modulus (1.5 K for bond-based), a push K h / m per particle.
  const double h = 0.01, m = 1900 * h * h * h, rate = 1.5 * 5e9 * h / m;
  EXPECT_NEAR(ground.critical_dt, std::sqrt(2.0 / (2.0 / (bonds * bonds) + rate)),
              1e-6 * bonds);  // (masses in float)
  EXPECT_LT(ground.critical_dt, bonds);
  ASSERT_EQ(ground.input.colliders.size(), 1u);
  EXPECT_EQ(ground.input.colliders[0].stiffness, real(1.5 * 5e9));
  const SetupResult indent = set_up(
      "[[colliders]]\nshape = \"sphere\"\ncenter = [0, 0.5, 0]\nradius = 0.1\nlaw = \"lammps_indent\"\n"
      "stiffness = 1e17\n");
  EXPECT_EQ(indent.critical_dt, bonds);
  EXPECT_EQ(indent.input.colliders[0].law, kLawLammpsIndent);
}

TEST(SceneSetup, FreeCollidersGetTheirShapesMassAndInertia) {
  const SetupResult s = set_up(
      "[[colliders]]\nshape = \"sphere\"\ncenter = [0, 0.5, 0]\nradius = 0.1\ndensity = 7800\n"
      "[[colliders]]\nshape = \"box\"\ncenter = [0, 0.5, 0.3]\nsize = [0.2, 0.4, 0.6]\nmass = 12\n"
      "[[colliders]]\nshape = \"cylinder\"\ncenter = [0, 0.5, 0.6]\nradius = 0.1\nlength = 0.4\nmass = 3\n");
  const auto& c = s.input.motion.colliders;
  ASSERT_EQ(c.size(), 3u);
  const double ball = 7800 * 4.0 / 3.0 * M_PI * 1e-3;
  EXPECT_NEAR(c[0].mass, ball, 1e-9 * ball);
  EXPECT_NEAR(c[0].inertia[0], 0.4 * ball * 0.01, 1e-9 * ball);
  EXPECT_NEAR(c[1].inertia[0], 12.0 / 12 * (0.16 + 0.36), 1e-12);  // m (b^2 + c^2) / 12
  EXPECT_NEAR(c[1].inertia[2], 12.0 / 12 * (0.04 + 0.16), 1e-12);
  EXPECT_NEAR(c[2].inertia[1], 0.5 * 3 * 0.01, 1e-12);  // about its axis: m r^2 / 2
  EXPECT_NEAR(c[2].inertia[0], 3 * (3 * 0.01 + 0.16) / 12, 1e-12);
  EXPECT_EQ(s.input.colliders[1].size.y, real(0.2));  // half extents
}

}  // namespace
}  // namespace pd

namespace pd {
namespace {

// `lattice_origin`: LAMMPS's `lattice sc 0.0005` + `create_atoms` in `region cylinder y 0 0 0.005
// -0.005 0` (examples/peri) makes 3,487 atoms, the lattice points of the cylinder, its surface
// included; a body on that lattice has the same points.
TEST(SceneSetup, LatticeOriginBuildsLammpsParticleSet) {
  const std::string scene = R"(
[simulation]
dt = 1e-7
[materials.m]
model = "bond_based"
density = 2200
bulk_modulus = 1.49e10
strain_limit = 5e-4
[[bodies]]
shape = "cylinder"
radius = 0.005
height = 0.005
center = [0, -0.0025, 0]
spacing = 0.0005
lattice_origin = [0, 0, 0]
material = "m"
)";
  const SetupResult s = setup_scene(parse_scene(scene, "scene.toml"), SetupOptions(1.0));
  const ParticleSet& ps = s.input.particles;
  ASSERT_EQ(ps.size(), 3487u);
  for (const Vec3& p : ps.rest) {
    for (real c : {p.x, p.y, p.z}) EXPECT_NEAR(double(c) / 0.0005, std::round(double(c) / 0.0005), 1e-6);
    EXPECT_LE(double(p.x) * p.x + double(p.z) * p.z, 0.005 * 0.005 * (1 + 1e-6));
    EXPECT_GE(p.y, real(-0.005 - 1e-9));
    EXPECT_LE(p.y, real(1e-9));
  }
  EXPECT_NEAR(double(ps.volume[0]), 1.25e-10, 1e-16);
  // A box on a shifted lattice: the points of [-0.001, 0.001] x ... at 0.0005 + k 0.001.
  const SetupResult b = setup_scene(
      parse_scene("[simulation]\ndt = 1e-7\n[materials.m]\nmodel = \"bond_based\"\ndensity = 2200\n"
                  "bulk_modulus = 1e9\nstrain_limit = 1e-3\n[[bodies]]\nsize = [0.002, 0.002, 0.002]\n"
                  "spacing = 0.001\nlattice_origin = [0.0005, 0.0005, 0.0005]\nmaterial = \"m\"\n",
                  "scene.toml"),
      SetupOptions(1.0));
  EXPECT_EQ(b.input.particles.size(), 8u);
}

TEST(SceneSetup, LatticeOriginIsForGridParticlesOnly) {
  try {
    parse_scene(
        "[simulation]\ndt = 1e-7\n[materials.m]\nmodel = \"bond_based\"\ndensity = 2200\n"
        "bulk_modulus = 1e9\nstrain_limit = 1e-3\n[[bodies]]\nsize = [0.01, 0.01, 0.01]\n"
        "spacing = 0.001\nparticles = \"voronoi\"\nlattice_origin = [0, 0, 0]\nmaterial = \"m\"\n",
        "scene.toml");
    ADD_FAILURE() << "lattice_origin accepted for Voronoi particles";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].lattice_origin"), std::string::npos) << e.what();
  }
}

// A shell deeper than its solid: one message naming the body's shell_thickness, before TetGen.
TEST(SceneSetup, AShellDeeperThanItsSolidNamesShellThickness) {
  const std::string scene = R"(
[simulation]
dt = 1e-7
[materials.glass]
density = 2440
bulk_modulus = 40e9
strain_limit = 5e-4
[[bodies]]
shape = "sphere"
radius = 0.05
spacing = 0.003
material = "glass"
particles = "shell"
shell_thickness = 0.06
)";
  try {
    setup_scene(parse_scene(scene, "scene.toml"), SetupOptions(1.0));
    ADD_FAILURE() << "a shell deeper than the sphere was set up";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bodies[0].shell_thickness"), std::string::npos) << what;
    EXPECT_NE(what.find("allowed: below"), std::string::npos) << what;
  }
}

// --scale that makes the spacing more than twice a box's smallest size is refused with the
// smallest scale allowed (it made one particle of the whole box, far too heavy).
TEST(SceneSetup, AScaleThatLeavesABoxNoParticleAlongAnAxisIsRefused) {
  const Scene scene = parse_scene(kWall, "scene.toml");
  EXPECT_NO_THROW(setup_scene(scene, SetupOptions(0.125)));  // spacing 0.02 for a 0.1 m box
  try {
    setup_scene(scene, SetupOptions(1e-6));
    ADD_FAILURE() << "a box of one particle was set up";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "--scale");
    EXPECT_NE(std::string(e.what()).find("--scale 0.000125 or more"), std::string::npos) << e.what();
  }
}

// A path anchor starts its particles at the velocity of its first segment (frame 0's kinetic
// energy, the energy balance's reference), as the same motion given as a velocity does.
TEST(SceneSetup, APathAnchorStartsAtItsFirstSegmentsVelocity) {
  const std::string box = "[[anchors]]\nbox_min = [-1, -1, -1]\nbox_max = [1, 0.03, 1]\n";
  const SetupResult path = set_up(box + "path = [[0, 0, 0, 0], [0.5, 1, 0, 0], [1, 1, 0, 0]]\n");
  const SetupResult velocity = set_up(box + "velocity = [2, 0, 0]\n");
  const ParticleSet& a = path.input.particles;
  int anchored = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.velocity[i].x, velocity.input.particles.velocity[i].x) << i;
    anchored += (a.flags[i] & kAnchored) != 0 && a.velocity[i].x == 2;
  }
  EXPECT_GT(anchored, 0);
}

// A mesh finer than the spacing gave 82,085 tets at a spacing asking for ~3,300 (and a time step
// 6.5 times shorter), and tet_keep_surface on a cube 6 for 1,000, both without a word.
TEST(SceneSetup, TetCountsFarFromTheSpacingAreWarnedOf) {
  EXPECT_EQ(tet_count_warning(3000, 0.2, 0.04, false, "bodies[0]"), "");  // 3125 a grid would hold
  EXPECT_EQ(
      tet_count_warning(82085, 0.7182, 0.06, false, "bodies[0]"),
      "bodies[0]: TetGen made 82085 tets, 25 times the 3325 a grid at spacing 0.06 m holds: it keeps every "
      "vertex of the surface, whose triangles are finer than the spacing (a coarser mesh, or particles = "
      "\"voronoi\", follows the spacing)");
  const std::string few = tet_count_warning(6, 0.001, 0.01, true, "bodies[2]");
  EXPECT_EQ(few.rfind("bodies[2]: TetGen made 6 tets, a 167th of the 1000 a grid at spacing 0.01 m holds: "
                      "tet_keep_surface = true keeps",
                      0),
            0u)
      << few;
}

}  // namespace
}  // namespace pd
