// The colliders' outputs of a run (host/app/collider_output.h): the shapes in colliders.obj, each
// frame's poses in colliders_NNNNN.csv and posed surfaces in colliders_NNNNN.vtu with their
// series, the series restored for a resumed run; and, where Blender is installed, the doc script
// of docs/output-formats.md placing every collider where the csv says.
#include "host/app/collider_output.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/geometry/collider_mesh.h"
#include "host/io/collider_file.h"
#include "tests/support/external_tools.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

// A box (half extents 0.1, 0.2, 0.3) and a sphere, and one particle for the plane's extent.
SimulationInput two_colliders() {
  SimulationInput in;
  in.particles.add({0, 0, 0}, {0, 0, 0}, real(1e-6), real(1e-3), real(1e-3), 0, 0);
  Collider box, sphere;
  box.shape = kColliderBox;
  box.size = {real(0.1), real(0.2), real(0.3)};
  sphere.shape = kColliderSphere;
  sphere.size = {real(0.05), 0, 0};
  in.colliders = {box, sphere};
  in.motion.colliders.resize(2);
  in.motion.colliders[1].mass = 2;
  return in;
}

// The box turned 90 degrees about z and moved, at frame k.
std::vector<Collider> posed(const SimulationInput& in, int k) {
  std::vector<Collider> c = in.colliders;
  const real turn[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  for (int i = 0; i < 9; ++i) c[0].rotation[i] = turn[i];
  c[0].center = {real(0.5 * k), 1, 2};
  c[1].center = {0, real(-0.1 * k), 0};
  return c;
}

class ColliderOutputTest : public testing::TempDirTest {};

TEST_F(ColliderOutputTest, WritesShapesPosesAndSurfaces) {
  const SimulationInput in = two_colliders();
  ColliderOutput out(dir_.string(), in, {TriMesh{}, TriMesh{}}, true);
  for (int k = 0; k < 3; ++k) out.write_frame(k, 0.1 * k, posed(in, k));
  const std::vector<TriMesh> shapes = read_collider_obj(path("colliders.obj"));
  ASSERT_EQ(shapes.size(), 2u);
  EXPECT_EQ(shapes[0].triangles.size(), 12u);  // the box
  const std::vector<ColliderState> frame2 = read_colliders_file(path(colliders_file_name(2)));
  ASSERT_EQ(frame2.size(), 2u);
  EXPECT_EQ(frame2[0].collider.center.x, real(1));
  EXPECT_NEAR(frame2[0].collider.rotation[1], -1, 1e-6);
  EXPECT_EQ(frame2[1].mass, 2);
  EXPECT_TRUE(fs::exists(path("colliders_00002.vtu")));
  const std::string series = testing::read_all(path("colliders.pvd"));
  EXPECT_NE(series.find("colliders_00002.vtu"), std::string::npos);
  // A resumed run takes the particles' series entries over.
  ColliderOutput again(dir_.string(), in, {TriMesh{}, TriMesh{}}, true);
  again.restore({{0.0, "frame_00000.vtu"}, {0.1, "frame_00001.vtu"}});
  const std::string restored = testing::read_all(path("colliders.pvd"));
  EXPECT_NE(restored.find("colliders_00001.vtu"), std::string::npos);
  EXPECT_EQ(restored.find("colliders_00002.vtu"), std::string::npos);
}

TEST_F(ColliderOutputTest, SceneWithoutCollidersWritesNothing) {
  SimulationInput in = two_colliders();
  in.colliders.clear();
  in.motion.colliders.clear();
  ColliderOutput out(dir_.string(), in, {}, true);
  out.write_frame(0, 0, {});
  EXPECT_EQ(entry_count(), 0u);
}

TEST_F(ColliderOutputTest, BlenderRunsTheDocScript) {
  const std::string script = testing::doc_script("docs/output-formats.md", "blender-colliders-script");
  ASSERT_FALSE(script.empty())
      << "no script after <!-- blender-colliders-script --> in docs/output-formats.md";
  const std::string blender = testing::find_program("blender");
  if (blender.empty()) GTEST_SKIP() << "blender is not on PATH (Debian: apt-get install blender)";
  const SimulationInput in = two_colliders();
  ColliderOutput out(dir_.string(), in, {TriMesh{}, TriMesh{}}, true);
  for (int k = 0; k < 3; ++k) out.write_frame(k, 0.1 * k, posed(in, k));
  std::ofstream(path("load.py")) << script
                                 << "bpy.context.scene.frame_set(2)\n"
                                    "for k, o in sorted(colliders.items()):\n"
                                    "    m = o.matrix_world\n"
                                    "    print('CHECK', k, *['%.9g' % m[r][3] for r in range(3)])\n";
  const std::string log =
      testing::run_command("timeout 300 " + blender + " --background --factory-startup --python " +
                           path("load.py") + " -- " + dir_.string());
  // Frame 2: the box's centre (1, 1, 2) and the sphere's (0, -0.2, 0), turned y-up to z-up.
  std::istringstream lines(log);
  std::string tag;
  int checked = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    int k = 0;
    double x, y, z;
    if (!(words >> tag >> k >> x >> y >> z) || tag != "CHECK") continue;
    const Vec3 c = posed(in, 2)[size_t(k)].center;
    EXPECT_NEAR(x, c.x, 1e-5);
    EXPECT_NEAR(y, -c.z, 1e-5);
    EXPECT_NEAR(z, c.y, 1e-5);
    ++checked;
  }
  EXPECT_EQ(checked, 2) << log;
}

}  // namespace
}  // namespace pd
