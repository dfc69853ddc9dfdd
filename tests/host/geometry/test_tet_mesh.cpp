// Face neighbours of a tet mesh (host/geometry/tet_mesh.h): found from the tets alone, they are
// TetGen's own .neigh, entry for entry.
#include "host/geometry/tet_mesh.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "host/geometry/shapes.h"
#include "host/geometry/tetgen.h"
#include "tests/host/geometry/geometry_fixtures.h"
#include "tests/support/external_tools.h"

namespace pd {
namespace {

using Tets = std::vector<std::array<int32_t, 4>>;

TEST(FaceNeighbors, TwoTetsShareOneFace) {
  // Tet 0's face opposite corner 0 is (1, 2, 3), tet 1's opposite corner 3 the same.
  const Tets tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  const Tets across = face_neighbors(tets, 5);
  const Tets expected = {{1, -1, -1, -1}, {-1, -1, -1, 0}};
  EXPECT_EQ(across, expected);
}

TEST(FaceNeighbors, CubeOfSixTetsAroundItsDiagonal) {
  // The cube's six tets around the diagonal 0-7 (corner v at x = v & 1, y = v >> 1 & 1,
  // z = v >> 2): each shares two faces with the tets beside it around the diagonal, and its
  // other two lie on the cube's faces (12 boundary triangles in all).
  const Tets tets = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  const Tets across = face_neighbors(tets, 8);
  int boundary = 0;
  for (size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const int32_t u = across[t][size_t(k)];
      if (u < 0) {
        ++boundary;
        continue;
      }
      // Symmetric: u names t across the same three vertices.
      int back = 0;
      for (int q = 0; q < 4; ++q) back += across[size_t(u)][size_t(q)] == int32_t(t);
      EXPECT_EQ(back, 1) << "tet " << t << " face " << k;
      int shared = 0;
      for (int32_t v : tets[size_t(u)])
        for (int q = 0; q < 4; ++q) shared += q != k && tets[t][size_t(q)] == v;
      EXPECT_EQ(shared, 3) << "tet " << t << " face " << k;
    }
  EXPECT_EQ(boundary, 12);
}

// Reads "count ..." then `count` rows of an index and four integers.
Tets read_rows(const std::string& path) {
  std::ifstream in(path);
  size_t count = 0;
  std::string rest;
  in >> count;
  std::getline(in, rest);
  Tets rows(count);
  long index = 0;
  for (auto& r : rows) {
    in >> index >> r[0] >> r[1] >> r[2] >> r[3];
    std::getline(in, rest);  // attributes
  }
  return rows;
}

TEST(FaceNeighbors, AreTetgensOwn) {
  const std::string tetgen = find_tetgen();
  if (tetgen.empty()) GTEST_SKIP() << "tetgen is not installed";
  test::ScratchDir dir("neighbours");
  TetgenOptions options;
  options.max_volume = 0.002;
  options.work_dir = dir.file("work");  // TetGen's input kept there
  const TetMesh mesh = tetrahedralize(torus_mesh(1, 0.3, 0.1), options, "torus");
  // TetGen again on the same input, now writing its neighbours (n), tets in its own orientation.
  const std::string out =
      testing::run_command("cd " + dir.file("work") + " && " + tetgen + " -pq1.414a0.002O0nzQ in.smesh");
  const Tets tets = read_rows(dir.file("work/in.1.ele"));
  const Tets neigh = read_rows(dir.file("work/in.1.neigh"));
  ASSERT_EQ(tets.size(), mesh.tets.size()) << out;
  ASSERT_EQ(neigh.size(), tets.size()) << out;
  EXPECT_EQ(face_neighbors(tets, mesh.vertices.size()), neigh);
}

}  // namespace
}  // namespace pd
