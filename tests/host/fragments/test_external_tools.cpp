// Optional: the files open in the tools users load them in. Blender runs the loading script of
// docs/fragments.md on a small run and must place each piece where the fragments file says;
// ParaView's Python opens the points and the pieces. Each test skips when its tool is absent
// (Debian: apt-get install blender python3-paraview).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "host/fragments/fragment_output.h"
#include "host/fragments/fragments_file.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

// The program's path if it is on PATH, else empty.
std::string find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir) / name;
    if (!dir.empty() && fs::exists(candidate)) return candidate.string();
  }
  return "";
}

// Runs `command`, returning its standard output and error.
std::string run(const std::string& command) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf;
  size_t got;
  while ((got = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), got);
  pclose(pipe);
  return out;
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
      out.process(f, bonds);
    }
    out.write_meshes();
  }
};

// The script marked <!-- blender-fragments-script --> in docs/fragments.md.
std::string doc_script() {
  std::ifstream in(std::string(PERIFRAC_SOURCE_DIR) + "/docs/fragments.md");
  std::string line, script;
  bool marked = false, inside = false;
  while (std::getline(in, line)) {
    if (inside && line == "```") break;
    if (inside) script += line + "\n";
    if (marked && line == "```python") inside = true;
    if (line == "<!-- blender-fragments-script -->") marked = true;
  }
  return script;
}

TEST_F(FragmentTools, BlenderRunsTheDocScript) {
  const std::string blender = find_program("blender");
  if (blender.empty()) GTEST_SKIP() << "blender is not on PATH (Debian: apt-get install blender)";
  const std::string script = doc_script();
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

}  // namespace
}  // namespace pd
