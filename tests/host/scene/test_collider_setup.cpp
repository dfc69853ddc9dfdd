// Collider set-up (host/scene/collider_setup.h): a closed mesh's volume, centroid and inertia; a
// mesh collider's frame, grid and probes; a free mesh box with the mass and inertia of the box
// collider of the same size; an open mesh as a fixed sheet but refused as a free body; and a
// particle resting on a mesh floor at the penetration the plane gives.
#include "host/scene/collider_setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cuda/engine/engine.h"
#include "cuda/kernels/colliders.h"
#include "host/geometry/collider_mesh.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "host/scene/scene_setup.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(ColliderSetup, MassPropertiesOfClosedMeshes) {
  TriMesh box = box_mesh({0.2, 0.4, 0.6});
  for (Vec3d& v : box.vertices) v = v + Vec3d{1, 2, 3};
  const MassProperties b = mass_properties(box);
  EXPECT_NEAR(b.volume, 0.048, 1e-12);
  EXPECT_NEAR(b.centroid[0], 1, 1e-12);
  EXPECT_NEAR(b.centroid[2], 3, 1e-12);
  EXPECT_NEAR(b.inertia[0], 0.048 / 12 * (0.16 + 0.36), 1e-12);  // V / 12 (b^2 + c^2)
  EXPECT_NEAR(b.inertia[8], 0.048 / 12 * (0.04 + 0.16), 1e-12);
  EXPECT_NEAR(b.inertia[1], 0, 1e-12);
  const MassProperties s = mass_properties(sphere_mesh(1, 0.02));
  const double v = 4 * kPi / 3;
  EXPECT_NEAR(s.volume, v, 2e-3 * v);
  EXPECT_NEAR(s.inertia[4], 0.4 * v, 4e-3 * 0.4 * v);
}

const std::string kBlock = R"(
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

class ColliderSetupTest : public testing::TempDirTest {
 protected:
  SetupResult set_up(const std::string& extra) {
    const std::string scene = path("scene.toml");
    std::ofstream(scene) << kBlock + extra;
    return setup_scene(load_scene(scene, {}), SetupOptions(1.0));
  }
};

TEST_F(ColliderSetupTest, FreeMeshBoxMovesLikeTheBoxCollider) {
  write_obj(box_mesh({0.2, 0.4, 0.6}), path("box.obj"));
  const SetupResult s = set_up(
      "[[colliders]]\nshape = \"mesh\"\nmesh = \"box.obj\"\ncenter = [0, 0.5, 0.3]\ndensity = 500\n"
      "[[colliders]]\nshape = \"box\"\ncenter = [0, 0.5, 0.3]\nsize = [0.2, 0.4, 0.6]\ndensity = 500\n");
  const ColliderScript &mesh = s.input.motion.colliders[0], &box = s.input.motion.colliders[1];
  EXPECT_NEAR(mesh.mass, box.mass, 1e-9 * box.mass);
  // The same principal moments (the mesh's frame is its principal axes, in another order).
  std::array<double, 3> a = mesh.inertia, b = box.inertia;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[size_t(k)], b[size_t(k)], 1e-9 * b[size_t(k)]);
  // Posed, the mesh is where the file put it around the centre: the box's corners.
  Collider posed = s.input.colliders[0];
  posed.center = {0, real(0.5), real(0.3)};
  for (int q = 0; q < 9; ++q) posed.rotation[q] = real(mesh.rotation[size_t(q)]);
  const TriMesh placed = posed_mesh(s.collider_meshes[0], posed);
  for (const Vec3d& v : placed.vertices) {
    EXPECT_NEAR(std::abs(v[0]), 0.1, 1e-6);
    EXPECT_NEAR(std::abs(v[1] - 0.5), 0.2, 1e-6);
    EXPECT_NEAR(std::abs(v[2] - 0.3), 0.3, 1e-6);
  }
  // Its grid and probes.
  const Collider& c = s.input.colliders[0];
  EXPECT_EQ(c.shape, kColliderMesh);
  EXPECT_EQ(s.input.collider_grids.size(), size_t(c.grid_dims[0]) * c.grid_dims[1] * c.grid_dims[2]);
  EXPECT_EQ(s.input.collider_probes[0].size(), 8u);  // the box mesh's corners
  EXPECT_TRUE(s.input.collider_probes[1].empty());
  // Near its surface (off the medial axis, where the field is linear): the distance to the face.
  const Vec3 near_face{real(0.01), real(0.52), real(0.58)};  // 2 cm inside the face z = 0.6
  EXPECT_NEAR(collider_surface(posed, near_face, s.input.collider_grids.data()).distance, -0.02, 1e-5);
  EXPECT_NEAR(collider_surface(posed, near_face, s.input.collider_grids.data()).normal.z, 1, 1e-5);
}

TEST_F(ColliderSetupTest, OpenMeshIsASheetButNotAFreeBody) {
  TriMesh sheet;
  sheet.vertices = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  sheet.triangles = {{0, 2, 1}, {0, 3, 2}};
  write_obj(sheet, path("sheet.obj"));
  const SetupResult s =
      set_up("[[colliders]]\nshape = \"mesh\"\nmesh = \"sheet.obj\"\ncenter = [0, -0.01, 0]\n");
  EXPECT_GT(shape_surface(s.input.colliders[0], {0, real(-0.05), 0}, s.input.collider_grids.data()).distance,
            0);
  try {
    set_up("[[colliders]]\nshape = \"mesh\"\nmesh = \"sheet.obj\"\ncenter = [0, -0.01, 0]\nmass = 2\n");
    ADD_FAILURE() << "a free open mesh was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("colliders[0].mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("open mesh"), std::string::npos) << e.what();
  }
}

TEST_F(ColliderSetupTest, TooFineAGridIsRefusedNamingTheCell) {
  write_obj(box_mesh({1, 1, 1}), path("box.obj"));
  try {
    set_up("[[colliders]]\nshape = \"mesh\"\nmesh = \"box.obj\"\ncenter = [0, -1, 0]\ncell = 1e-4\n");
    ADD_FAILURE() << "a grid of 1e12 nodes was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("colliders[0].cell"), std::string::npos) << e.what();
  }
}

TEST_F(ColliderSetupTest, ParticleRestsOnAMeshFloorAsOnAPlane) {
  // One cube of the block resting on the top face of a mesh slab and on a plane: the same depth.
  write_obj(box_mesh({1, 0.2, 1}), path("slab.obj"));
  auto rest_height = [&](const std::string& floor) {
    SetupResult s = set_up(floor + "[world]\ngravity = [0, -9.81, 0]\n");
    SimulationInput in = s.input;
    ParticleSet one;
    one.add({0, real(0.01), 0}, {0, 0, 0}, in.particles.volume[0], in.particles.mass[0], real(1), 0, 0);
    in.particles = one;
    in.step.dt = real(2e-6);
    in.colliders[0].damping = real(1);
    auto engine = make_cpu_engine(in);
    engine->advance(20000);
    ParticleState st;
    engine->read_state(st);
    return double(0.01 + st.disp[0].y);
  };
  const double plane = rest_height("[[colliders]]\nshape = \"plane\"\ncenter = [0, 0, 0]\n");
  const double mesh =
      rest_height("[[colliders]]\nshape = \"mesh\"\nmesh = \"slab.obj\"\ncenter = [0, -0.1, 0]\n");
  EXPECT_NEAR(mesh, plane, 1e-6);
  EXPECT_NEAR(plane, 0.005, 1e-5);
}

}  // namespace
}  // namespace pd
