// Pre-cracks, weakened surfaces and shards: the segment-triangle test, the bonds the engine
// removes or weakens at set-up, and that weakened bonds break first.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "cuda/engine/bond_cuts.h"
#include "tests/support/broken_bonds.h"
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

// A crack far larger than the bodies (a random walk of huge steps) is listed only where bonds
// start: set up at once, with the same bonds removed as the same plane of the bodies' size.
TEST(BondCuts, AHugeCrackCostsNoMoreThanOneAcrossTheBodies) {
  const double lambda = 1e-3, cut = 4.5e-3;
  auto in = lattice_block(10, 5, 5, lambda);
  in.cuts = plane_x(cut, 0);
  const int64_t removed = make_cpu_engine(in)->family_stats().cuts.removed;
  in.cuts = plane_x(cut, 0, 1e30);
  EXPECT_EQ(make_cpu_engine(in)->family_stats().cuts.removed, removed);
  EXPECT_GT(removed, 0);
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
  const auto broken = testing::broken_bond_set(*e);
  for (const auto& [i, j] : broken) EXPECT_NE(ps.rest[size_t(i)].x < cut, ps.rest[size_t(j)].x < cut) << i;
  EXPECT_EQ(broken.size() % 2, 0u);
}

TEST(BondCuts, WeakenedPlaneBreaksFirstBondBased) {
  expect_weak_plane_breaks_first(lattice_block(12, 4, 4, 1e-3, 1e-3), 5.5e-3);
}

TEST(BondCuts, WeakenedPlaneBreaksFirstStateBased) {
  expect_weak_plane_breaks_first(state_block(12, 4, 4, 1e-3, 1e-3, false), 5.5e-3);
}

// Shards: cells of 3 x 3 x 3 particles (along x shifted by one, so x = 5.5 lambda, the middle of a
// 12-particle bar, lies inside cell 2's particles 5, 6, 7), bonds between cells at strength
// `strength` / 255, strain limits raised by its inverse.
void make_cubic_shards(SimulationInput& in, int nx, int ny, double lambda, uint8_t strength) {
  auto& ps = in.particles;
  ps.shard.resize(ps.size());
  ps.shard_strength.assign(ps.size(), strength);
  for (size_t i = 0; i < ps.size(); ++i) {
    const long cx = (std::lround(ps.rest[i].x / lambda) + 1) / 3, cy = std::lround(ps.rest[i].y / lambda) / 3,
               cz = std::lround(ps.rest[i].z / lambda) / 3;
    ps.shard[i] = int32_t((cz * ((ny + 2) / 3) + cy) * ((nx + 3) / 3) + cx);
    ps.strain_limit0[i] *= real(255.0 / strength);
  }
}

// The strength cut_bonds gives each slot of the engine's families of `in` (shards and `cuts`),
// passed to check(i, j, strength) per bond; returns the counts.
template <class Check>
BondCutCounts check_slot_strengths(const SimulationInput& in, const std::vector<CutTriangle>& cuts,
                                   double longest, Check check) {
  BondLists lists;
  make_cpu_engine(in)->read_bonds(lists);
  std::vector<uint8_t> strength;
  const BondCutCounts counts = cut_bonds(cuts, in.particles.rest, in.particles.body, longest, lists, strength,
                                         in.particles.shard, in.particles.shard_strength);
  EXPECT_EQ(strength.size(), lists.neighbor.size());
  const BondsView v = lists.view();
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int64_t slot = v.slot(i, k);
      check(i, bond_partner(v.neighbor[slot]), strength.empty() ? 255 : strength[size_t(slot)]);
    }
  return counts;
}

TEST(BondCuts, ShardsWeakenExactlyTheBondsBetweenCells) {
  const double lambda = 1e-3;
  auto in = lattice_block(9, 6, 6, lambda);
  make_cubic_shards(in, 9, 6, lambda, 85);
  const auto& shard = in.particles.shard;
  int64_t between = 0;
  const BondCutCounts counts = check_slot_strengths(in, {}, 0, [&](int32_t i, int32_t j, int strength) {
    const bool across = shard[size_t(i)] != shard[size_t(j)];
    between += across;
    EXPECT_EQ(strength, across ? 85 : 255) << i << "-" << j;
  });
  EXPECT_GT(between, 0);
  EXPECT_EQ(counts.weakened, between);
  EXPECT_EQ(counts.removed, 0);
  EXPECT_EQ(make_cpu_engine(in)->family_stats().cuts.weakened, between);  // the engine applied the same
}

// A zone of cells over part of a body: the bonds from a cell to a particle in none (-1, strength
// 255) are faces too, from both ends; bonds between particles in none keep their strength.
TEST(BondCuts, ShardsZoneEdgeIsAFace) {
  const double lambda = 1e-3;
  auto in = lattice_block(9, 6, 6, lambda);
  make_cubic_shards(in, 9, 6, lambda, 85);
  auto& ps = in.particles;
  for (size_t i = 0; i < ps.size(); ++i)
    if (ps.rest[i].x > 4.5e-3) {
      ps.shard[i] = -1;
      ps.shard_strength[i] = 255;
    }
  int64_t edge = 0, outside = 0;
  check_slot_strengths(in, {}, 0, [&](int32_t i, int32_t j, int strength) {
    const int32_t a = ps.shard[size_t(i)], b = ps.shard[size_t(j)];
    edge += (a < 0) != (b < 0);
    outside += a < 0 && b < 0;
    EXPECT_EQ(strength, a != b ? 85 : 255) << i << "-" << j;
  });
  EXPECT_GT(edge, 0);
  EXPECT_GT(outside, 0);
}

TEST(BondCuts, ShardsAndATriangleTakeTheWeaker) {
  const double lambda = 1e-3;
  auto in = lattice_block(9, 6, 6, lambda);
  make_cubic_shards(in, 9, 6, lambda, 85);
  // A plane at x = 4.5 lambda (inside the second column of cells) at strength 0.2 (51 / 255).
  const auto& ps = in.particles;
  check_slot_strengths(in, plane_x(4.5e-3, 0.2), 4e-3, [&](int32_t i, int32_t j, int strength) {
    const bool across = ps.shard[size_t(i)] != ps.shard[size_t(j)];
    const bool crosses = (ps.rest[size_t(i)].x < 4.5e-3) != (ps.rest[size_t(j)].x < 4.5e-3);
    EXPECT_EQ(strength, crosses ? 51 : (across ? 85 : 255)) << i << "-" << j;
  });
}

// Pulled apart at its middle, which lies inside a cell, a bar of shards whose cells hold 5 times
// the material's limit breaks only between cells: every bond broken joins two cells, from both
// ends (without shards it parts at the middle).
void expect_shards_break_between_cells(SimulationInput in) {
  const double lambda = 1e-3;
  in = testing::pulled_apart(std::move(in), 12, lambda, 1);
  make_cubic_shards(in, 12, 6, lambda, 51);
  const auto& shard = in.particles.shard;
  auto e = make_cpu_engine(in);
  e->advance(300);
  const auto broken = testing::broken_bond_set(*e);
  for (const auto& [i, j] : broken) EXPECT_NE(shard[size_t(i)], shard[size_t(j)]) << i;
  EXPECT_GT(broken.size(), 100u);
  EXPECT_EQ(broken.size() % 2, 0u);
  // The same bar without shards breaks bonds inside the cells.
  SimulationInput plain = in;
  plain.particles.shard.clear();
  plain.particles.shard_strength.clear();
  for (size_t i = 0; i < plain.particles.size(); ++i) plain.particles.strain_limit0[i] *= real(51.0 / 255);
  auto p = make_cpu_engine(plain);
  p->advance(300);
  int64_t inside = 0;
  for (const auto& [i, j] : testing::broken_bond_set(*p)) inside += shard[size_t(i)] == shard[size_t(j)];
  EXPECT_GT(inside, 0);
}

TEST(BondCuts, ShardsBreakBetweenCellsBondBased) {
  expect_shards_break_between_cells(lattice_block(12, 6, 6, 1e-3, 2e-4));
}

TEST(BondCuts, ShardsBreakBetweenCellsStateBased) {
  expect_shards_break_between_cells(state_block(12, 6, 6, 1e-3, 2e-4, false));
}

}  // namespace
}  // namespace pd
