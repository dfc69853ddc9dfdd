// Rest-space fragment surfaces of grid bodies: closed, outward, with the right area and volume.
#include "host/fragments/cube_mesh.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/random.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

using CubeMeshTest = testing::TempDirTest;

// Closed and consistently oriented: every directed edge of an object's quads appears as often as
// its reverse; on a manifold surface exactly once each (each edge shared by exactly two faces).
// Cubes of one piece that touch only along an edge make that edge non-manifold (four faces).
void expect_closed(const FragmentMesh& m, size_t o, bool manifold = true) {
  std::map<std::pair<int32_t, int32_t>, int> edges;
  for (int64_t q = m.quad_start[o]; q < m.quad_start[o + 1]; ++q)
    for (int k = 0; k < 4; ++k)
      ++edges[{m.quads[size_t(q)][size_t(k)], m.quads[size_t(q)][size_t((k + 1) % 4)]}];
  for (const auto& [e, count] : edges) {
    if (manifold) EXPECT_EQ(count, 1) << "edge " << e.first << "-" << e.second << " of object " << o;
    const auto reverse = edges.find({e.second, e.first});
    EXPECT_EQ(reverse == edges.end() ? 0 : reverse->second, count)
        << "edge " << e.first << "-" << e.second << " of object " << o << " is open";
  }
  for (int64_t q = m.quad_start[o]; q < m.quad_start[o + 1]; ++q)
    for (int32_t v : m.quads[size_t(q)]) {
      EXPECT_GE(v, m.vertex_start[o]);
      EXPECT_LT(v, m.vertex_start[o + 1]);
    }
}

double area(const FragmentMesh& m, size_t o) {
  double a = 0;
  for (int64_t q = m.quad_start[o]; q < m.quad_start[o + 1]; ++q) {
    const auto& f = m.quads[size_t(q)];
    const Eigen::Vector3d &p0 = m.vertices[size_t(f[0])], &p1 = m.vertices[size_t(f[1])],
                          &p2 = m.vertices[size_t(f[2])], &p3 = m.vertices[size_t(f[3])];
    a += 0.5 * ((p1 - p0).cross(p2 - p0).norm() + (p2 - p0).cross(p3 - p0).norm());
  }
  return a;
}

// Signed volume (divergence theorem): positive when the faces point outwards.
double volume(const FragmentMesh& m, size_t o) {
  double v = 0;
  for (int64_t q = m.quad_start[o]; q < m.quad_start[o + 1]; ++q) {
    const auto& f = m.quads[size_t(q)];
    const Eigen::Vector3d &p0 = m.vertices[size_t(f[0])], &p1 = m.vertices[size_t(f[1])],
                          &p2 = m.vertices[size_t(f[2])], &p3 = m.vertices[size_t(f[3])];
    v += (p0.dot(p1.cross(p2)) + p0.dot(p2.cross(p3))) / 6;
  }
  return v;
}

struct Block {
  SimulationInput in;
  BondLists bonds;
  ElementAdjacency adjacency;
  std::vector<real> spacing;
};

Block block(int nx, int ny, int nz, double lambda) {
  Block b;
  b.in = testing::lattice_block(nx, ny, nz, lambda);
  make_cpu_engine(b.in)->read_bonds(b.bonds);
  b.spacing = particle_spacing(b.in.particles, b.in.materials);
  b.adjacency = grid_adjacency(b.bonds, b.in.particles.rest, b.spacing);
  return b;
}

TEST_F(CubeMeshTest, UnbrokenBlockIsClosedWithTheRightAreaAndVolume) {
  const int nx = 7, ny = 5, nz = 4;
  const double lambda = 2e-3;
  const Block b = block(nx, ny, nz, lambda);
  const FragmentMesh m = cube_fragment_mesh(b.adjacency, b.in.particles.rest, b.spacing,
                                            components_from_ids(std::vector<int32_t>(140, 0)));
  ASSERT_EQ(m.objects(), 1u);
  EXPECT_EQ(m.ids[0], 0);
  expect_closed(m, 0);
  const double faces = 2.0 * (nx * ny + ny * nz + nz * nx);
  EXPECT_EQ(m.quads.size(), size_t(faces));
  EXPECT_EQ(m.vertices.size(), size_t((nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1)));
  EXPECT_NEAR(area(m, 0), faces * lambda * lambda, 1e-6 * faces * lambda * lambda);
  EXPECT_NEAR(volume(m, 0), nx * ny * nz * lambda * lambda * lambda,
              1e-5 * nx * ny * nz * lambda * lambda * lambda);
}

TEST_F(CubeMeshTest, CutBlockGivesTwoClosedPiecesThatMeet) {
  const int nx = 8, ny = 3, nz = 2;
  const double lambda = 1e-3;
  const Block b = block(nx, ny, nz, lambda);
  std::vector<int32_t> id(size_t(nx * ny * nz));
  for (size_t i = 0; i < id.size(); ++i) id[i] = (i % nx) < 3 ? 0 : 3;
  const FragmentMesh m =
      cube_fragment_mesh(b.adjacency, b.in.particles.rest, b.spacing, components_from_ids(id));
  ASSERT_EQ(m.objects(), 2u);
  EXPECT_EQ(m.ids, (std::vector<int32_t>{0, 3}));
  for (size_t o = 0; o < 2; ++o) {
    const int w = o == 0 ? 3 : 5;
    expect_closed(m, o);
    EXPECT_NEAR(area(m, o), 2.0 * (w * ny + ny * nz + nz * w) * lambda * lambda, 1e-9);
    EXPECT_NEAR(volume(m, o), w * ny * nz * lambda * lambda * lambda, 1e-14);
  }
  // The cut faces of both pieces lie on the same plane x = 2.5 lambda (rest positions are cube
  // centres at k lambda).
  double left_max = -1, right_min = 1;
  for (int64_t v = m.vertex_start[0]; v < m.vertex_start[1]; ++v)
    left_max = std::max(left_max, m.vertices[size_t(v)].x());
  for (int64_t v = m.vertex_start[1]; v < m.vertex_start[2]; ++v)
    right_min = std::min(right_min, m.vertices[size_t(v)].x());
  EXPECT_NEAR(left_max, 2.5 * lambda, 1e-10);  // float32 rest positions
  EXPECT_EQ(left_max, right_min);
}

TEST_F(CubeMeshTest, JitteredGridAndLonelyCubesStayClosed) {
  // Jittered rest positions with grid adjacency given explicitly; every third particle alone.
  const int nx = 5, ny = 4, nz = 3;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, 1.0, 1e-3, 0.3);
  std::vector<std::pair<int32_t, int32_t>> pairs;
  auto at = [&](int i, int j, int k) { return int32_t(i + nx * (j + ny * k)); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (i + 1 < nx) pairs.push_back({at(i, j, k), at(i + 1, j, k)});
        if (j + 1 < ny) pairs.push_back({at(i, j, k), at(i, j + 1, k)});
        if (k + 1 < nz) pairs.push_back({at(i, j, k), at(i, j, k + 1)});
      }
  std::vector<int32_t> id(size_t(nx * ny * nz), 0);
  for (size_t i = 0; i < id.size(); i += 3) id[i] = int32_t(i);
  id[0] = 0;
  const Components c = components_from_ids(id);
  const FragmentMesh m = cube_fragment_mesh(adjacency_from_pairs(id.size(), pairs), in.particles.rest,
                                            std::vector<real>(id.size(), real(1)), c);
  ASSERT_EQ(m.objects(), c.count());
  double total = 0;
  for (size_t o = 0; o < m.objects(); ++o) {
    expect_closed(m, o, false);
    EXPECT_GT(volume(m, o), 0);
    total += volume(m, o);
    if (c.size(o) == 1) EXPECT_EQ(m.quad_start[o + 1] - m.quad_start[o], 6);
  }
  // The pieces tile the jittered block: their volumes add up to the whole block's.
  const FragmentMesh whole = cube_fragment_mesh(adjacency_from_pairs(id.size(), pairs), in.particles.rest,
                                                std::vector<real>(id.size(), real(1)),
                                                components_from_ids(std::vector<int32_t>(id.size(), 0)));
  EXPECT_NEAR(total, volume(whole, 0), 1e-9);
}

TEST_F(CubeMeshTest, RejectsAdjacencyThatIsNotACubeGrid) {
  const std::vector<Vec3> rest = {{0, 0, 0}, {1, 0, 0}, {1.1f, 0.1f, 0}};
  const Components c = components_from_ids({0, 0, 0});
  const std::vector<real> side(3, real(1));
  EXPECT_THROW(cube_fragment_mesh(adjacency_from_pairs(3, {{0, 1}, {0, 2}}), rest, side, c),
               std::invalid_argument);
  const std::vector<Vec3> ring = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};  // 0-1-2-0 does not close on a grid
  EXPECT_THROW(cube_fragment_mesh(adjacency_from_pairs(3, {{0, 1}, {1, 2}, {2, 0}}), ring, side, c),
               std::invalid_argument);
  EXPECT_THROW(cube_fragment_mesh(adjacency_from_pairs(2, {}), rest, side, c), std::invalid_argument);
}

TEST_F(CubeMeshTest, ObjFileListsObjectsVerticesAndQuads) {
  const Block b = block(3, 2, 2, 0.5);
  std::vector<int32_t> id(12, 0);
  for (size_t i = 0; i < 12; ++i) id[i] = i % 3 == 2 ? 2 : 0;
  const FragmentMesh m =
      cube_fragment_mesh(b.adjacency, b.in.particles.rest, b.spacing, components_from_ids(id));
  const std::string p = path("fragments.obj");
  write_obj(p, m);
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> objects;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int32_t, 4>> quads;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "o") objects.push_back(line.substr(2));
    if (tag == "v") {
      Eigen::Vector3d v;
      words >> v.x() >> v.y() >> v.z();
      vertices.push_back(v);
    }
    if (tag == "f") {
      std::array<int32_t, 4> q{};
      for (int32_t& k : q) words >> k;
      quads.push_back(q);
    }
  }
  EXPECT_EQ(objects, (std::vector<std::string>{"fragment_0", "fragment_2"}));
  ASSERT_EQ(vertices.size(), m.vertices.size());
  for (size_t v = 0; v < vertices.size(); ++v) EXPECT_LT((vertices[v] - m.vertices[v]).norm(), 1e-8);
  ASSERT_EQ(quads.size(), m.quads.size());
  for (size_t q = 0; q < quads.size(); ++q)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(quads[q][size_t(k)], m.quads[q][size_t(k)] + 1);
}

}  // namespace
}  // namespace pd
