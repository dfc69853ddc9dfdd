// The cube elements of grid particles: 8 corners and 6 outward quads per particle, corners shared
// by neighbouring cubes merged, faces bordering the neighbour across them; grids that are not
// cube grids are refused.
#include "host/fragments/cube_complex.h"

#include <gtest/gtest.h>

#include <numeric>
#include <stdexcept>

#include "host/fragments/adjacency.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

TEST(CubeComplex, BlockSharesCornersAndFacesBorderTheirNeighbours) {
  const int nx = 4, ny = 3, nz = 2;
  const double lambda = 2e-3;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, lambda);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  const std::vector<real> spacing = particle_spacing(in.particles, in.materials);
  const ElementAdjacency adj = grid_adjacency(bonds, in.particles.rest, spacing);
  std::vector<int32_t> all(in.particles.size());
  std::iota(all.begin(), all.end(), 0);
  const ElementComplex c = cube_complex(adj, in.particles.rest, spacing, all);
  check(c, in.particles.size());
  ASSERT_EQ(c.size(), all.size());
  EXPECT_EQ(c.vertices.size(), size_t((nx + 1) * (ny + 1) * (nz + 1)));
  size_t surface = 0;
  for (size_t e = 0; e < c.size(); ++e) {
    EXPECT_EQ(c.particle[e], int32_t(e));
    EXPECT_EQ(c.corners(e), 8);
    EXPECT_EQ(c.face_start[e + 1] - c.face_start[e], 6);
    EXPECT_NEAR(element_volume(c, e), lambda * lambda * lambda,
                1e-6 * lambda * lambda * lambda);  // float rest
    for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f) {
      const int32_t o = c.face_other[size_t(f)];
      surface += o < 0;
      if (o < 0) continue;
      // The neighbour lists the same four vertices on its face back to this cube.
      std::vector<int32_t> mine, theirs;
      for (int64_t k = c.face_corner_start[size_t(f)]; k < c.face_corner_start[size_t(f) + 1]; ++k)
        mine.push_back(c.corner_vertex[size_t(c.face_corner[size_t(k)])]);
      for (int64_t g = c.face_start[size_t(o)]; g < c.face_start[size_t(o) + 1]; ++g)
        if (c.face_other[size_t(g)] == int32_t(e))
          for (int64_t k = c.face_corner_start[size_t(g)]; k < c.face_corner_start[size_t(g) + 1]; ++k)
            theirs.push_back(c.corner_vertex[size_t(c.face_corner[size_t(k)])]);
      std::sort(mine.begin(), mine.end());
      std::sort(theirs.begin(), theirs.end());
      EXPECT_EQ(mine, theirs);
    }
  }
  EXPECT_EQ(surface, size_t(2 * (nx * ny + ny * nz + nz * nx)));
}

TEST(CubeComplex, RejectsAdjacencyThatIsNotACubeGrid) {
  const std::vector<Vec3> rest = {{0, 0, 0}, {1, 0, 0}, {1.1f, 0.1f, 0}};
  const std::vector<real> side(3, real(1));
  const std::vector<int32_t> all{0, 1, 2};
  EXPECT_THROW(cube_complex(adjacency_from_pairs(3, {{0, 1}, {0, 2}}), rest, side, all),
               std::invalid_argument);
  const std::vector<Vec3> ring = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};  // 0-1-2-0 does not close on a grid
  EXPECT_THROW(cube_complex(adjacency_from_pairs(3, {{0, 1}, {1, 2}, {2, 0}}), ring, side, all),
               std::invalid_argument);
  EXPECT_THROW(cube_complex(adjacency_from_pairs(2, {}), rest, side, all), std::invalid_argument);
  // A cube next to a particle that is not one.
  EXPECT_THROW(cube_complex(adjacency_from_pairs(3, {{0, 1}}), rest, side, {0}), std::invalid_argument);
}

}  // namespace
}  // namespace pd
