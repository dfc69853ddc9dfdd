// Rearranging tet particles (host/geometry/particle_order.h): every per-particle array, the
// adjacency and the tets with their neighbour indices follow the new order.
#include <gtest/gtest.h>

#include <stdexcept>

#include "host/geometry/curve_order.h"
#include "host/geometry/particle_order.h"
#include "host/geometry/tet_particles.h"

namespace pd {
namespace {

// Two tets sharing the face {1, 2, 3}: across corner 0 of the first, across corner 4 (its 4th) of
// the second.
TetMesh two_tets() {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.neighbors = {{1, -1, -1, -1}, {-1, -1, -1, 0}};
  return m;
}

TEST(ParticleOrder, TetsAndTheirNeighboursFollow) {
  ParticleGeometry g = tet_particles(two_tets());
  ASSERT_EQ(g.size(), 2u);
  const ParticleGeometry before = g;
  g.mass = {1.0, 2.0};
  reorder_particles(g, {1, 0});
  EXPECT_EQ(g.tets.tets[0], before.tets.tets[1]);
  EXPECT_EQ(g.tets.tets[1], before.tets.tets[0]);
  EXPECT_EQ(g.position[0], before.position[1]);
  EXPECT_EQ(g.volume[1], before.volume[0]);
  EXPECT_EQ(g.lambda[0], before.lambda[1]);
  EXPECT_EQ(g.mass, (std::vector<double>{2.0, 1.0}));
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_EQ(g.position[t], g.tets.barycenter(t));
    // The neighbour across the shared face is now the other index.
    int shared = 0;
    for (int32_t u : g.tets.neighbors[t]) shared += u == int32_t(1 - t);
    EXPECT_EQ(shared, 1) << "tet " << t;
    ASSERT_EQ(g.adjacency.degree(t), 1);
    EXPECT_EQ(g.adjacency.neighbor[size_t(g.adjacency.offset[t])], int32_t(1 - t));
  }
}

// tet_particles gives its particles in curve order (sorting them again changes nothing).
TEST(ParticleOrder, TetParticlesComeInCurveOrder) {
  TetMesh m = two_tets();
  std::swap(m.tets[0], m.tets[1]);
  m.neighbors = {{-1, -1, -1, 1}, {0, -1, -1, -1}};
  const ParticleGeometry a = tet_particles(two_tets()), b = tet_particles(m);
  EXPECT_EQ(morton_order(a.position), (std::vector<int32_t>{0, 1}));
  EXPECT_EQ(a.tets.tets, b.tets.tets);
  EXPECT_EQ(a.tets.neighbors, b.tets.neighbors);
}

TEST(ParticleOrder, OnlyTetsAndWholePermutations) {
  ParticleGeometry g = tet_particles(two_tets());
  EXPECT_THROW(reorder_particles(g, {0}), std::logic_error);
  g.kind = ElementKind::voronoi;
  EXPECT_THROW(reorder_particles(g, {0, 1}), std::logic_error);
}

}  // namespace
}  // namespace pd
