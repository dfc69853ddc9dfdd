// Pre-cracks and weakened surfaces: the segment-triangle test, the bonds the engine removes or
// weakens at set-up, and that weakened bonds break first.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "cuda/engine/bond_cuts.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

using testing::lattice_block;
using testing::state_block;

// A square in the plane x = x0, covering y and z in [-1, 1] (two triangles).
std::vector<CutTriangle> plane_x(double x0, double strength, double half = 1) {
  CutTriangle a, b;
  a.corner = {{{x0, -half, -half}, {x0, half, -half}, {x0, half, half}}};
  b.corner = {{{x0, -half, -half}, {x0, half, half}, {x0, -half, half}}};
  a.strength = b.strength = strength;
  return {a, b};
}

TEST(BondCuts, SegmentTriangleCrossing) {
  CutTriangle t;
  t.corner = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  EXPECT_TRUE(segment_crosses_triangle({0.2, 0.2, -1}, {0.2, 0.2, 1}, t));
  EXPECT_TRUE(segment_crosses_triangle({0.2, 0.2, 1}, {0.2, 0.2, -1}, t));
  EXPECT_FALSE(segment_crosses_triangle({0.8, 0.8, -1}, {0.8, 0.8, 1}, t));   // beyond the hypotenuse
  EXPECT_FALSE(segment_crosses_triangle({0.2, 0.2, 0.5}, {0.2, 0.2, 2}, t));  // stops short
  EXPECT_FALSE(segment_crosses_triangle({0.2, 0.2, 0}, {0.2, 0.2, 1}, t));    // open segment: an end on it
  EXPECT_FALSE(segment_crosses_triangle({-1, 0.2, 0.5}, {1, 0.2, 0.5}, t));   // parallel
  EXPECT_TRUE(segment_crosses_triangle({0.5, 0.5, -1}, {0.5, 0.5, 1}, t));    // through the edge
}

// Partners of every particle, as the engine stores them.
std::vector<std::set<int32_t>> partners(Engine& e) {
  BondLists b;
  e.read_bonds(b);
  const BondsView v = b.view();
  std::vector<std::set<int32_t>> out(size_t(v.n));
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) out[size_t(i)].insert(bond_partner(v.neighbor[v.slot(i, k)]));
  return out;
}

// A plane between two lattice layers removes exactly the bonds across it, from both ends, and
// the families keep every other bond.
TEST(BondCuts, PreCrackRemovesExactlyTheBondsAcross) {
  const double lambda = 1e-3, cut = 4.5e-3;
  auto in = lattice_block(10, 5, 5, lambda);
  const auto whole = partners(*make_cpu_engine(in));
  in.cuts = plane_x(cut, 0);
  auto e = make_cpu_engine(in);
  const auto cracked = partners(*e);
  int64_t across = 0;
  for (size_t i = 0; i < whole.size(); ++i)
    for (int32_t j : whole[i]) {
      const bool crosses = (in.particles.rest[i].x < cut) != (in.particles.rest[size_t(j)].x < cut);
      across += crosses;
      EXPECT_EQ(cracked[i].count(j), crosses ? 0u : 1u) << i << "-" << j;
    }
  EXPECT_GT(across, 0);
  EXPECT_EQ(e->family_stats().cuts.removed, across);
  EXPECT_EQ(e->family_stats().bonds + across,
            make_cpu_engine(lattice_block(10, 5, 5, lambda))->family_stats().bonds);
  EXPECT_EQ(e->broken_bonds(), 0);  // a pre-crack is a free surface, not damage
}

// A triangle limited to another body leaves this one whole.
TEST(BondCuts, CutsOfAnotherBodyDoNothing) {
  auto in = lattice_block(6, 4, 4, 1e-3);
  in.cuts = plane_x(2.5e-3, 0);
  for (auto& t : in.cuts) t.body = 1;
  EXPECT_EQ(make_cpu_engine(in)->family_stats().cuts.removed, 0);
}

// Pulled apart by its ends, a bar with a weakened plane breaks there first: when the first
// bonds break, every broken bond crosses the plane, from both ends.
void expect_weak_plane_breaks_first(SimulationInput in, double cut) {
  in.cuts = plane_x(cut, 0.5);
  const auto& ps = in.particles;
  double xmax = 0;
  for (const Vec3& x : ps.rest) xmax = std::max(xmax, double(x.x));
  for (size_t i = 0; i < ps.size(); ++i) {
    const double x = ps.rest[i].x;
    if (x > 1.5e-3 && x < xmax - 1.5e-3) continue;
    in.particles.flags[i] |= kAnchored;
    in.particles.velocity[i] = {real(x < cut ? -0.2 : 0.2), 0, 0};
  }
  auto e = make_cpu_engine(in);
  EXPECT_GT(e->family_stats().cuts.weakened, 0);
  while (e->broken_bonds() == 0 && e->step() < 20000) e->advance(20);
  ASSERT_GT(e->broken_bonds(), 0);
  BondLists b;
  e->read_bonds(b);
  const BondsView v = b.view();
  int64_t broken = 0;
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t nb = v.neighbor[v.slot(i, k)];
      if (bond_intact(nb)) continue;
      ++broken;
      EXPECT_NE(ps.rest[size_t(i)].x < cut, ps.rest[size_t(bond_partner(nb))].x < cut) << i;
    }
  EXPECT_EQ(broken % 2, 0);
}

TEST(BondCuts, WeakenedPlaneBreaksFirstBondBased) {
  expect_weak_plane_breaks_first(lattice_block(12, 4, 4, 1e-3, 1e-3), 5.5e-3);
}

TEST(BondCuts, WeakenedPlaneBreaksFirstStateBased) {
  expect_weak_plane_breaks_first(state_block(12, 4, 4, 1e-3, 1e-3, false), 5.5e-3);
}

}  // namespace
}  // namespace pd
