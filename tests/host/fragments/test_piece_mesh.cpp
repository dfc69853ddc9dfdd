// Rest-space fragment surfaces for every element kind: each piece is closed and consistently
// oriented, encloses the volume of its particles, and the OBJ file lists what was built.
#include "host/fragments/piece_mesh.h"

#include <gtest/gtest.h>

#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>

#include "host/fragments/adjacency.h"
#include "host/fragments/cube_complex.h"
#include "host/fragments/tet_complex.h"
#include "host/fragments/voronoi_complex.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/host/fragments/mesh_checks.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

using PieceMeshTest = testing::TempDirTest;

// The cube complex of a lattice block and its grid adjacency.
ElementComplex block_cubes(const SimulationInput& in, const ElementAdjacency& adj) {
  std::vector<int32_t> all(in.particles.size());
  std::iota(all.begin(), all.end(), 0);
  return cube_complex(adj, in.particles.rest, particle_spacing(in.particles, in.materials), all);
}

ElementAdjacency block_adjacency(const SimulationInput& in) {
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  return grid_adjacency(bonds, in.particles.rest, particle_spacing(in.particles, in.materials));
}

// Every object closed and outward; its volume is the sum of its elements' `volume` within
// `relative` of the larger; returns the objects' volumes.
std::vector<double> expect_closed_pieces(const FragmentMesh& m, const Components& c,
                                         const std::vector<double>& volume, double relative,
                                         bool manifold = true) {
  std::vector<double> out;
  EXPECT_EQ(m.objects(), c.count());
  for (size_t o = 0; o < m.objects(); ++o) {
    EXPECT_EQ(m.ids[o], c.component_id(o));
    const auto polygons = testing::object_polygons(m, o);
    testing::expect_closed(polygons, manifold, "piece " + std::to_string(m.ids[o]));
    for (const auto& p : polygons)
      for (int32_t v : p) {
        EXPECT_GE(v, m.vertex_start[o]);
        EXPECT_LT(v, m.vertex_start[o + 1]);
      }
    double expected = 0;
    for (int32_t k = c.start[o]; k < c.start[o + 1]; ++k) expected += volume[size_t(c.members[size_t(k)])];
    const double got = testing::enclosed_volume(m.vertices, polygons, m.vertices[size_t(m.vertex_start[o])]);
    EXPECT_NEAR(got, expected, relative * expected) << "piece " << m.ids[o];
    out.push_back(got);
  }
  return out;
}

TEST_F(PieceMeshTest, UnbrokenCubeBlockIsClosedWithTheRightAreaAndVolume) {
  const int nx = 7, ny = 5, nz = 4;
  const double lambda = 2e-3;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, lambda);
  const ElementComplex cubes = block_cubes(in, block_adjacency(in));
  const Components c = components_from_ids(std::vector<int32_t>(140, 0));
  const FragmentMesh m = fragment_pieces(cubes, c);
  // Float rest positions: corners to ~1e-7 relative.
  expect_closed_pieces(m, c, std::vector<double>(140, lambda * lambda * lambda), 1e-5);
  const double faces = 2.0 * (nx * ny + ny * nz + nz * nx);
  EXPECT_EQ(m.polygons(), size_t(faces));
  EXPECT_EQ(m.vertices.size(), size_t((nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1)));
  EXPECT_NEAR(testing::area(m.vertices, testing::object_polygons(m, 0)), faces * lambda * lambda,
              1e-6 * faces * lambda * lambda);
}

TEST_F(PieceMeshTest, CutCubeBlockGivesTwoClosedPiecesThatMeet) {
  const int nx = 8, ny = 3, nz = 2;
  const double lambda = 1e-3;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, lambda);
  const ElementComplex cubes = block_cubes(in, block_adjacency(in));
  std::vector<int32_t> id(size_t(nx * ny * nz));
  for (size_t i = 0; i < id.size(); ++i) id[i] = (i % nx) < 3 ? 0 : 3;
  const Components c = components_from_ids(id);
  const FragmentMesh m = fragment_pieces(cubes, c);
  ASSERT_EQ(m.objects(), 2u);
  EXPECT_EQ(m.ids, (std::vector<int32_t>{0, 3}));
  expect_closed_pieces(m, c, std::vector<double>(id.size(), lambda * lambda * lambda), 1e-5);
  for (size_t o = 0; o < 2; ++o) {
    const int w = o == 0 ? 3 : 5;
    EXPECT_NEAR(testing::area(m.vertices, testing::object_polygons(m, o)),
                2.0 * (w * ny + ny * nz + nz * w) * lambda * lambda, 1e-9);
  }
  // The cut faces of both pieces lie on the same plane x = 2.5 lambda (rest positions are cube
  // centres at k lambda).
  double left_max = -1, right_min = 1;
  for (int64_t v = m.vertex_start[0]; v < m.vertex_start[1]; ++v)
    left_max = std::max(left_max, m.vertices[size_t(v)][0]);
  for (int64_t v = m.vertex_start[1]; v < m.vertex_start[2]; ++v)
    right_min = std::min(right_min, m.vertices[size_t(v)][0]);
  EXPECT_NEAR(left_max, 2.5 * lambda, 1e-10);  // float32 rest positions
  EXPECT_EQ(left_max, right_min);
}

TEST_F(PieceMeshTest, JitteredGridAndLonelyCubesStayClosed) {
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
  std::vector<int32_t> id(size_t(nx * ny * nz), 0), all(id.size());
  for (size_t i = 0; i < id.size(); i += 3) id[i] = int32_t(i);
  id[0] = 0;
  std::iota(all.begin(), all.end(), 0);
  const ElementComplex cubes = cube_complex(adjacency_from_pairs(id.size(), pairs), in.particles.rest,
                                            std::vector<real>(id.size(), real(1)), all);
  // The jittered cubes' corners are merged at the mean, so each cube's volume is its element's.
  std::vector<double> volume(id.size());
  for (size_t e = 0; e < cubes.size(); ++e) volume[e] = element_volume(cubes, e);
  const Components c = components_from_ids(id);
  // Cubes of one piece that touch only along an edge make that edge non-manifold (four faces).
  const std::vector<double> v = expect_closed_pieces(fragment_pieces(cubes, c), c, volume, 1e-12, false);
  // The pieces tile the jittered block: their volumes add up to the whole block's.
  const FragmentMesh whole = fragment_pieces(cubes, components_from_ids(std::vector<int32_t>(id.size(), 0)));
  EXPECT_NEAR(std::accumulate(v.begin(), v.end(), 0.0),
              testing::enclosed_volume(whole.vertices, testing::object_polygons(whole, 0), {0, 0, 0}), 1e-9);
}

TEST_F(PieceMeshTest, TetPiecesAreClosedAndHoldTheirTets) {
  const double side = 1e-3;
  const EmbeddedTets box = testing::box_tets(4, 3, 3, side);
  const ElementComplex tets = tet_complex(box);
  std::vector<double> volume(tets.size());
  for (size_t e = 0; e < tets.size(); ++e) volume[e] = element_volume(tets, e);
  // Left of x = 2 one piece (label 0), every fifth tet of the right on its own, the rest another
  // piece (label 1).
  std::vector<int32_t> id(tets.size());
  for (size_t t = 0; t < id.size(); ++t) {
    double x = 0;
    for (int32_t v : box.tets[t]) x += 0.25 * box.vertices[size_t(v)][0];
    id[t] = x < 2 * side ? 0 : t % 5 == 0 ? int32_t(t) : 1;
  }
  const Components c = components_from_ids(id);
  const std::vector<double> v = expect_closed_pieces(fragment_pieces(tets, c), c, volume, 1e-12, false);
  EXPECT_NEAR(std::accumulate(v.begin(), v.end(), 0.0), 36 * side * side * side,
              1e-12 * 36 * side * side * side);
}

// Voronoi cells cut to a convex and a non-convex object: every piece, whether a half, a lonely
// cell on the surface or inside, is closed and encloses exactly its particles' volume (the
// geometry stage's exact cell-in-object volumes). Both volumes are exact in real arithmetic and
// computed by different formulas, so they agree to round-off: at most 4e-14 relative seen on
// these shapes; 1e-11 leaves room for other meshes.
TEST_F(PieceMeshTest, VoronoiPiecesAreClosedAndHoldTheirParticlesVolume) {
  for (const bool torus : {false, true}) {
    SCOPED_TRACE(torus ? "torus" : "sphere");
    const TriMesh solid = torus ? torus_mesh(0.03, 0.012, 0.004) : sphere_mesh(0.02, 0.003);
    const ParticleGeometry g = voronoi_particles(solid, 0.004, 3, 100000, "solid");
    VoronoiComplexReport report;
    const ElementComplex cells = voronoi_complex(g, 0, &report);
    check(cells, g.size());
    EXPECT_GT(report.boundary_cells, 0u);
    EXPECT_EQ(report.failed_faces, 0u);
    for (size_t e = 0; e < cells.size(); ++e)
      EXPECT_NEAR(element_volume(cells, e), g.volume[e], 1e-11 * g.volume[e]);
    // Whole; halves; halves with every seventh cell alone.
    for (int split = 0; split < 3; ++split) {
      std::vector<int32_t> id(g.size(), 0);
      int32_t right = -1;
      for (size_t i = 0; i < g.size(); ++i) {
        if (split == 0) continue;
        if (g.position[i][0] > 0.001) id[i] = right < 0 ? right = int32_t(i) : right;
        if (split == 2 && i % 7 == 3) id[i] = int32_t(i);
      }
      const Components c = components_from_ids(id);
      const FragmentMesh m = fragment_pieces(cells, c);
      expect_closed_pieces(m, c, g.volume, 1e-11, false);
    }
  }
}

TEST_F(PieceMeshTest, ObjFileListsObjectsVerticesAndPolygons) {
  const SimulationInput in = testing::lattice_block(3, 2, 2, 0.5);
  const ElementComplex cubes = block_cubes(in, block_adjacency(in));
  std::vector<int32_t> id(12, 0);
  for (size_t i = 0; i < 12; ++i) id[i] = i % 3 == 2 ? 2 : 0;
  const FragmentMesh m = fragment_pieces(cubes, components_from_ids(id));
  const std::string p = path("fragments.obj");
  write_obj(p, m);
  std::ifstream in_file(p);
  std::string line;
  std::vector<std::string> objects;
  std::vector<Vec3d> vertices;
  std::vector<std::vector<int32_t>> polygons;
  while (std::getline(in_file, line)) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "o") objects.push_back(line.substr(2));
    if (tag == "v") {
      Vec3d v;
      words >> v[0] >> v[1] >> v[2];
      vertices.push_back(v);
    }
    if (tag == "f") {
      std::vector<int32_t> q;
      for (int32_t k; words >> k;) q.push_back(k - 1);
      polygons.push_back(q);
    }
  }
  EXPECT_EQ(objects, (std::vector<std::string>{"fragment_0", "fragment_2"}));
  ASSERT_EQ(vertices.size(), m.vertices.size());
  for (size_t v = 0; v < vertices.size(); ++v) EXPECT_LT(norm(vertices[v] - m.vertices[v]), 1e-8);
  ASSERT_EQ(polygons.size(), m.polygons());
  for (size_t q = 0; q < polygons.size(); ++q)
    EXPECT_EQ(polygons[q], std::vector<int32_t>(m.polygon_vertex.begin() + m.polygon_start[q],
                                                m.polygon_vertex.begin() + m.polygon_start[q + 1]));
  EXPECT_THROW(fragment_pieces(cubes, components_from_ids({0, 0})), std::invalid_argument);
}

}  // namespace
}  // namespace pd
