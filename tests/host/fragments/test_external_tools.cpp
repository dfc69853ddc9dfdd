// Optional: the files open in the tools users load them in. Blender runs the loading scripts of
// docs/fragments.md on a small run: the pieces must be placed where the fragments file says, and
// the crack meshes imported with their faces and crack material; ParaView's Python opens the
// particle series, points, pieces and crack meshes. Each test skips when its tool is absent
// (Debian: apt-get install blender python3-paraview).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "host/fragments/fragment_output.h"
#include "host/fragments/fragments_file.h"
#include "host/io/vtk_writer.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/support/external_tools.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

using testing::doc_script;
using testing::find_program;

// Runs `command`, returning its standard output and error.
std::string run(const std::string& command) {
  return testing::run_command(command);
}

constexpr int kNx = 8, kNy = 4, kNz = 3;
constexpr double kLambda = 0.1;

// A block whose right half (x index >= 4) breaks off at frame 1 and turns about z by 0.3 rad per
// frame around (4, 0, 0) lambda, while the whole block rises 0.05 m per frame.
class FragmentTools : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    const SimulationInput in = testing::lattice_block(kNx, kNy, kNz, kLambda);
    BondLists bonds;
    make_cpu_engine(in)->read_bonds(bonds);
    FragmentOutput out(in, bonds, {dir_.string(), 0, true});
    PvdSeries series(dir_.string(), "particles");
    for (int frame = 0; frame < 3; ++frame) {
      if (frame == 1) {
        const BondsView v = bonds.view();
        for (int32_t i = 0; i < v.n; ++i)
          for (int32_t k = 0; k < v.count[i]; ++k) {
            const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
            if ((i % kNx < 4) != (j % kNx < 4)) bonds.neighbor[size_t(v.slot(i, k))] = ~j;
          }
      }
      const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3 * frame, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      FrameData f;
      f.frame = frame;
      for (size_t i = 0; i < in.particles.size(); ++i) {
        const Vec3 x = in.particles.rest[i];
        Eigen::Vector3d p(x.x, x.y, x.z);
        if (i % kNx >= 4)
          p = r * (p - Eigen::Vector3d(4 * kLambda, 0, 0)) + Eigen::Vector3d(4 * kLambda, 0, 0);
        p.y() += 0.05 * frame;
        f.position.push_back({real(p.x()), real(p.y()), real(p.z())});
        f.velocity.push_back({0, 0, 0});
        f.damage.push_back(0);
        f.body.push_back(0);
      }
      f.time = 0.1 * frame;
      out.process(f, bonds);
      series.add(f.time, frame_file_name(frame, "vtu"));
      write_vtu(path(frame_file_name(frame, "vtu")), f);
    }
    out.write_meshes();
  }

  // The last frame's crack mesh: both halves, the cut drawn from both sides.
  CrackSurface last_crack_mesh() const { return read_crack_mesh(path("crack_mesh_00002.ply")); }
};

// The words after `tag` on each line of `log` that starts with it.
std::vector<std::vector<std::string>> tagged(const std::string& log, const std::string& tag) {
  std::vector<std::vector<std::string>> out;
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string first, w;
    if (!(words >> first) || first != tag) continue;
    out.emplace_back();
    while (words >> w) out.back().push_back(w);
  }
  return out;
}

TEST_F(FragmentTools, BlenderRunsTheDocScript) {
  const std::string blender = find_program("blender");
  if (blender.empty()) GTEST_SKIP() << "blender is not on PATH (Debian: apt-get install blender)";
  const std::string script = doc_script("docs/fragments.md", "blender-fragments-script");
  ASSERT_FALSE(script.empty()) << "no script after <!-- blender-fragments-script --> in docs/fragments.md";
  // The doc script, then the world matrix of every piece at every frame.
  std::ofstream(path("load.py"))
      << script
      << "for frame in (0, 1, 2):\n"
         "    bpy.context.scene.frame_set(frame)\n"
         "    for piece in ids:\n"
         "        m = pieces[int(piece)].matrix_world\n"
         "        print('CHECK', frame, int(piece), *['%.9g' % m[r][c] for r in range(3) "
         "for c in range(4)])\n";
  const std::string log = run("timeout 300 " + blender + " --background --factory-startup --python " +
                              path("load.py") + " -- " + dir_.string());

  // Expected: z-up turn of the fragment transform that holds each piece (pieces 0 and 4).
  const Eigen::Matrix3d y_up_to_z_up =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  std::istringstream lines(log);
  std::string line;
  int checked = 0;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string tag;
    int frame = 0, piece = 0;
    if (!(words >> tag >> frame >> piece) || tag != "CHECK") continue;
    Eigen::Matrix<double, 3, 4> got;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) words >> got(r, c);
    const FragmentsFrame f = read_fragments_file(path(fragments_file_name(frame)));
    const Fragment& holder = frame == 0 || piece == 0 ? f.fragments.front() : f.fragments.back();
    Eigen::Matrix<double, 3, 4> expected;
    expected << y_up_to_z_up * holder.rotation, y_up_to_z_up * holder.translation;
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-5) << "piece " << piece << " at frame " << frame;
    ++checked;
  }
  EXPECT_EQ(checked, 6) << log;
}

TEST_F(FragmentTools, BlenderImportsTheCrackMeshes) {
  const std::string blender = find_program("blender");
  if (blender.empty()) GTEST_SKIP() << "blender is not on PATH (Debian: apt-get install blender)";
  const std::string script = doc_script("docs/fragments.md", "blender-cracks-script");
  ASSERT_FALSE(script.empty()) << "no script after <!-- blender-cracks-script --> in docs/fragments.md";
  // The doc script, then each frame's object: its size, the faces of the crack material and the
  // frames it is visible at; then the PLY of the last frame through Blender's PLY importer.
  std::ofstream(path("cracks.py"))
      << script
      << "for o in sorted(root.children, key=lambda o: o.name):\n"
         "    crack = [i for i, m in enumerate(o.data.materials) if m and m.name.startswith('crack')]\n"
         "    seen = []\n"
         "    for f in (0, 1, 2):\n"
         "        bpy.context.scene.frame_set(f)\n"
         "        if not o.hide_render: seen.append(f)\n"
         "    print('OBJECT', len(o.data.vertices), len(o.data.polygons),\n"
         "          sum(p.material_index in crack for p in o.data.polygons), *seen)\n"
         "bpy.ops.import_mesh.ply(filepath=os.path.join(OUT, 'crack_mesh_00002.ply'))\n"
         "m = bpy.context.selected_objects[0].data\n"
         "print('PLY', len(m.vertices), len(m.polygons))\n";
  const std::string log = run("timeout 300 " + blender + " --background --factory-startup --python " +
                              path("cracks.py") + " -- " + dir_.string());
  const auto objects = tagged(log, "OBJECT");
  ASSERT_EQ(objects.size(), 3u) << log;
  const CrackSurface last = last_crack_mesh();
  for (size_t frame = 0; frame < 3; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const CrackSurface s = read_crack_mesh(path(crack_mesh_file_name(int64_t(frame), "obj")));
    ASSERT_EQ(objects[frame].size(), 4u) << log;  // visible at its own frame only
    EXPECT_EQ(std::stoul(objects[frame][0]), s.vertices.size());
    EXPECT_EQ(std::stoul(objects[frame][1]), s.triangles.size());
    EXPECT_EQ(std::stoul(objects[frame][2]), s.crack_count());
    EXPECT_EQ(std::stoul(objects[frame][3]), frame);
  }
  EXPECT_GT(last.crack_count(), 0u);
  const auto ply = tagged(log, "PLY");
  ASSERT_EQ(ply.size(), 1u) << log;
  EXPECT_EQ(std::stoul(ply[0][0]), last.vertices.size());
  EXPECT_EQ(std::stoul(ply[0][1]), last.triangles.size());
}

TEST_F(FragmentTools, ParaViewOpensPointsAndPieces) {
  const std::string pvpython = find_program("pvpython");
  if (pvpython.empty()) GTEST_SKIP() << "pvpython is not on PATH (Debian: apt-get install python3-paraview)";
  std::ofstream(path("open.py")) << "import sys\n"
                                    "from paraview.simple import OpenDataFile, servermanager\n"
                                    "d = sys.argv[1]\n"
                                    "points = servermanager.Fetch(OpenDataFile(d + '/points_00002.ply'))\n"
                                    "print('POINTS', points.GetNumberOfPoints(), *points.GetPoint(95))\n"
                                    "pieces = servermanager.Fetch(OpenDataFile(d + '/fragments.obj'))\n"
                                    "print('PIECES', pieces.GetNumberOfCells())\n";
  const std::string log = run("timeout 300 " + pvpython + " " + path("open.py") + " " + dir_.string());
  std::istringstream lines(log);
  std::string line, tag;
  bool points = false, pieces = false;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    words >> tag;
    if (tag == "POINTS") {
      size_t n = 0;
      double x = 0, y = 0, z = 0;
      words >> n >> x >> y >> z;
      EXPECT_EQ(n, size_t(kNx * kNy * kNz));
      // Particle 95: the last cube, in the right half, turned by 0.6 rad and raised by 0.1 m.
      const Eigen::Vector3d p = Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()) *
                                    Eigen::Vector3d(3 * kLambda, 3 * kLambda, 2 * kLambda) +
                                Eigen::Vector3d(4 * kLambda, 0.1, 0);
      EXPECT_LT((Eigen::Vector3d(x, y, z) - p).norm(), 1e-6) << line;
      points = true;
    }
    if (tag == "PIECES") {
      size_t cells = 0;
      words >> cells;
      EXPECT_EQ(cells, size_t(2 * (2 * (4 * kNy + kNy * kNz + kNz * 4))));  // two 4 x 4 x 3 halves, quads
      pieces = true;
    }
  }
  EXPECT_TRUE(points && pieces) << log;
}

TEST_F(FragmentTools, ParaViewOpensTheSeriesAndCrackMeshes) {
  const std::string pvpython = find_program("pvpython");
  if (pvpython.empty()) GTEST_SKIP() << "pvpython is not on PATH (Debian: apt-get install python3-paraview)";
  std::ofstream(path("series.py"))
      << "import sys\n"
         "from paraview.simple import OpenDataFile, UpdatePipeline, servermanager\n"
         "d = sys.argv[1]\n"
         "r = OpenDataFile(d + '/particles.pvd')\n"
         "print('TIMES', *r.TimestepValues)\n"
         "UpdatePipeline(time=r.TimestepValues[-1], proxy=r)\n"
         "g = servermanager.Fetch(r)\n"
         "print('LAST', g.GetFieldData().GetArray('TimeValue').GetValue(0), g.GetNumberOfPoints(),\n"
         "      *g.GetPointData().GetArray('component').GetRange())\n"
         "for ext in ('obj', 'ply'):\n"
         "    m = servermanager.Fetch(OpenDataFile(d + '/crack_mesh_00002.' + ext))\n"
         "    ids = m.GetCellData().GetArray('GroupIds')\n"
         "    crack = sum(ids.GetValue(c) == 1 for c in range(m.GetNumberOfCells())) if ids else -1\n"
         "    print('CRACK', ext, m.GetNumberOfPoints(), m.GetNumberOfCells(), crack)\n";
  const std::string log = run("timeout 300 " + pvpython + " " + path("series.py") + " " + dir_.string());
  // The series: three frames 0.1 apart; the last one has both fragments (ids 0 and 4).
  const auto times = tagged(log, "TIMES");
  ASSERT_EQ(times.size(), 1u) << log;
  ASSERT_EQ(times[0].size(), 3u) << log;
  for (size_t k = 0; k < 3; ++k) EXPECT_NEAR(std::stod(times[0][k]), 0.1 * double(k), 1e-12);
  const auto last = tagged(log, "LAST");
  ASSERT_EQ(last.size(), 1u) << log;
  EXPECT_NEAR(std::stod(last[0][0]), 0.2, 1e-12);
  EXPECT_EQ(std::stoul(last[0][1]), size_t(kNx * kNy * kNz));
  EXPECT_EQ(std::stod(last[0][2]), 0);
  EXPECT_EQ(std::stod(last[0][3]), 4);
  // The crack mesh: every triangle, and in the OBJ the crack group (GroupIds 1); the PLY reader
  // keeps no face properties (-1).
  const CrackSurface s = last_crack_mesh();
  const auto crack = tagged(log, "CRACK");
  ASSERT_EQ(crack.size(), 2u) << log;
  for (const auto& c : crack) {
    SCOPED_TRACE(c[0]);
    EXPECT_EQ(std::stoul(c[1]), s.vertices.size());
    EXPECT_EQ(std::stoul(c[2]), s.triangles.size());
    EXPECT_EQ(std::stol(c[3]), c[0] == "obj" ? long(s.crack_count()) : -1L);
  }
}

}  // namespace
}  // namespace pd
