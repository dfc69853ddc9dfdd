// Procedural shapes are closed, outward, centred, and enclose their analytic volume to the
// accuracy of their facets; each exports to OBJ and reads back as a valid solid.
#include <gtest/gtest.h>

#include <cmath>

#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

constexpr double kPi = 3.14159265358979323846;

void expect_closed_solid(TriMesh mesh, double volume, double rel_tol) {
  const MeshReport r = check_solid(mesh, "shape", {});
  EXPECT_FALSE(r.flipped);
  EXPECT_EQ(r.holes, 0);
  EXPECT_EQ(r.welded_vertices, 0);
  EXPECT_NEAR(signed_volume(mesh), volume, rel_tol * volume);
  const Vec3d c = bounds(mesh).center();
  for (double x : c) EXPECT_NEAR(x, 0, 1e-12);
}

TEST(Shapes, ClosedWithTheirVolumes) {
  expect_closed_solid(box_mesh({1, 2, 3}), 6, 1e-14);
  expect_closed_solid(sphere_mesh(1, 0.05), 4 * kPi / 3, 2e-3);
  expect_closed_solid(cylinder_mesh(0.5, 2, 0.05), kPi * 0.25 * 2, 2e-3);
  expect_closed_solid(torus_mesh(1, 0.25, 0.02), 2 * kPi * kPi * 1 * 0.0625, 2e-3);
}

TEST(Shapes, VaseIsAThinClosedWall) {
  const TriMesh vase = vase_mesh(0.1, 0.3, 0.005, 0.005);
  TriMesh copy = vase;
  check_solid(copy, "vase", {});
  const double v = signed_volume(vase);
  // The wall: about (outer area) x thickness; far less than the solid of revolution.
  EXPECT_GT(v, 0);
  EXPECT_LT(v, 0.2 * kPi * 0.01 * 0.3);
  const TriMesh sheet = vase_sheet(0.1, 0.3, 0.005);
  EXPECT_EQ(boundary_loops(sheet, "sheet").size(), 1u);  // the rim
}

TEST(Shapes, ExportAsObjAndReadBack) {
  test::ScratchDir dir("shapes");
  const TriMesh torus = torus_mesh(1, 0.25, 0.1);
  write_obj(torus, dir.file("torus.obj"));
  TriMesh back = read_mesh(dir.file("torus.obj"));
  check_solid(back, dir.file("torus.obj"), {});
  EXPECT_DOUBLE_EQ(signed_volume(back), signed_volume(torus));
}

}  // namespace
}  // namespace pd
