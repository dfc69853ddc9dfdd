// `perifrac shapes`: each body's solid written as a mesh file that reads back closed, at the
// body's place, with the shape's volume; a broken mesh body is reported with its scene key.
#include "host/app/export_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/scene/scene.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

constexpr double kPi = 3.14159265358979323846;

class ExportShapes : public testing::TempDirTest {
 protected:
  std::string scene(const std::string& bodies) {
    const std::string p = path("scene.toml");
    std::ofstream(p) << "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
                     << bodies;
    return p;
  }
};

TEST_F(ExportShapes, ProceduralBodiesReadBackClosedWithTheirVolumes) {
  ShapeExportOptions o;
  o.scene = scene(
      "[[bodies]]\nname = \"slab\"\nmaterial = \"glass\"\ncenter = [1.0, 0.0, 0.0]\nsize = [0.2, 0.1, 0.05]\n"
      "spacing = 0.01\n"
      "[[bodies]]\nname = \"ball\"\nmaterial = \"glass\"\nshape = \"sphere\"\nradius = 0.05\n"
      "center = [0.0, 0.5, 0.0]\nspacing = 0.0025\n"
      "[[bodies]]\nname = \"ring\"\nmaterial = \"glass\"\nshape = \"torus\"\nradius = 0.1\n"
      "tube_radius = 0.03\nspacing = 0.0025\n");
  o.out = path("shapes");
  o.format = "ply";
  ASSERT_EQ(export_shapes_command(o), 0);
  // The box is exact; the curved shapes are inscribed polyhedra with edges of the spacing (2.5 mm
  // on radii of 30-50 mm): their volume falls short by about (edge / radius)^2 / 4 < 0.2%; 1%
  // allows for the vertex layout.
  const struct {
    const char* name;
    double volume, tolerance;
    Vec3d center;
  } expected[] = {{"slab", 0.2 * 0.1 * 0.05, 1e-12, {1, 0, 0}},
                  {"ball", 4 * kPi / 3 * 0.05 * 0.05 * 0.05, 1e-2, {0, 0.5, 0}},
                  {"ring", 2 * kPi * kPi * 0.1 * 0.03 * 0.03, 1e-2, {0, 0, 0}}};
  for (const auto& e : expected) {
    SCOPED_TRACE(e.name);
    const std::string file = path("shapes/" + std::string(e.name) + ".ply");
    TriMesh mesh = read_mesh(file);
    EXPECT_NO_THROW(check_solid(mesh, file, {false}));
    EXPECT_NEAR(signed_volume(mesh), e.volume, e.tolerance * e.volume);
    const Vec3d c = bounds(mesh).center();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], e.center[k], 1e-9);
  }
}

TEST_F(ExportShapes, BrokenMeshBodyIsReportedWithItsKey) {
  std::ofstream(path("open.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  ShapeExportOptions o;
  o.scene = scene("[[bodies]]\nname = \"part\"\nmaterial = \"glass\"\nshape = \"mesh\"\nmesh = \"" +
                  path("open.obj") + "\"\nspacing = 0.01\n");
  o.out = path("shapes");
  try {
    export_shapes_command(o);
    FAIL() << "an open mesh was exported";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].mesh"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path("shapes/part.obj")));
}

// Bodies of one name each get a file of their own (the name and the body's index).
TEST_F(ExportShapes, BodiesOfOneNameDoNotOverwriteEachOther) {
  ShapeExportOptions o;
  const std::string body =
      "[[bodies]]\nname = \"twin\"\nmaterial = \"glass\"\nsize = [0.1, 0.1, 0.1]\nspacing = 0.01\n";
  o.scene = scene(body + body + "center = [1.0, 0.0, 0.0]\n");
  o.out = path("shapes");
  o.format = "obj";
  ASSERT_EQ(export_shapes_command(o), 0);
  EXPECT_NEAR(bounds(read_mesh(path("shapes/twin_0.obj"))).center()[0], 0, 1e-12);
  EXPECT_NEAR(bounds(read_mesh(path("shapes/twin_1.obj"))).center()[0], 1, 1e-12);
}

}  // namespace
}  // namespace pd
