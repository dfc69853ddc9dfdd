// Element adjacency and connected components: grid face neighbours from engine families, a block
// cut by a plane of broken bonds, union-find against breadth-first search on random graphs.
#include "host/fragments/components.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <queue>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/fragments/adjacency.h"
#include "host/geometry/random.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

using testing::bond_lists;
using testing::break_bond;

// Breadth-first reference: every particle's id is the smallest particle reachable from it over
// adjacent pairs whose bond is intact in both families.
std::vector<int32_t> bfs_ids(const ElementAdjacency& adj, const BondLists& b) {
  const BondsView v = b.view();
  auto intact_from = [&](int32_t i, int32_t j) {
    for (int32_t k = 0; k < v.count[i]; ++k)
      if (bond_partner(v.neighbor[v.slot(i, k)]) == j) return bond_intact(v.neighbor[v.slot(i, k)]);
    return false;
  };
  const size_t n = adj.size();
  std::vector<int32_t> id(n, -1);
  for (size_t s = 0; s < n; ++s) {
    if (id[s] >= 0) continue;
    std::queue<int32_t> q;
    q.push(int32_t(s));
    id[s] = int32_t(s);
    while (!q.empty()) {
      const int32_t i = q.front();
      q.pop();
      for (int64_t e = adj.offset[size_t(i)]; e < adj.offset[size_t(i) + 1]; ++e) {
        const int32_t j = adj.neighbor[size_t(e)];
        if (id[size_t(j)] < 0 && intact_from(i, j) && intact_from(j, i)) {
          id[size_t(j)] = int32_t(s);
          q.push(j);
        }
      }
    }
  }
  return id;
}

// Checks the grouping arrays of `c` against its per-particle ids.
void expect_consistent(const Components& c) {
  ASSERT_EQ(c.start.back(), int32_t(c.id.size()));
  for (size_t k = 0; k < c.count(); ++k) {
    if (k > 0) {
      EXPECT_LT(c.component_id(k - 1), c.component_id(k));
    }
    for (int32_t m = c.start[k]; m < c.start[k + 1]; ++m) {
      const size_t i = size_t(c.members[size_t(m)]);
      EXPECT_EQ(c.index[i], int32_t(k));
      EXPECT_EQ(c.id[i], c.component_id(k));
      if (m > c.start[k]) {
        EXPECT_LT(c.members[size_t(m) - 1], c.members[size_t(m)]);
      }
    }
  }
}

TEST(Adjacency, FromPairsIsSymmetricAndSorted) {
  const ElementAdjacency a = adjacency_from_pairs(4, {{2, 0}, {0, 1}, {3, 2}});
  EXPECT_EQ(a.offset, (std::vector<int64_t>{0, 2, 3, 5, 6}));
  EXPECT_EQ(a.neighbor, (std::vector<int32_t>{1, 2, 0, 0, 3, 2}));
  EXPECT_THROW(adjacency_from_pairs(3, {{0, 3}}), std::invalid_argument);
  EXPECT_THROW(adjacency_from_pairs(3, {{1, 1}}), std::invalid_argument);
  EXPECT_EQ(adjacency_from_pairs(3, {{0, 1}, {1, 0}, {0, 1}}).neighbor, (std::vector<int32_t>{1, 0}));
}

TEST(Adjacency, GridFaceNeighboursFromEngineFamilies) {
  const int nx = 6, ny = 5, nz = 4;
  const double lambda = 1e-3;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, lambda);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  const ElementAdjacency a =
      grid_adjacency(bonds, in.particles.rest, particle_spacing(in.particles, in.materials));
  // Every particle's face neighbours are the particles one lattice step away.
  auto at = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::vector<int32_t> expected;
        for (auto [di, dj, dk] :
             {std::array{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}) {
          const int ii = i + di, jj = j + dj, kk = k + dk;
          if (ii >= 0 && ii < nx && jj >= 0 && jj < ny && kk >= 0 && kk < nz)
            expected.push_back(at(ii, jj, kk));
        }
        const size_t p = size_t(at(i, j, k));
        std::vector<int32_t> got(a.neighbor.begin() + a.offset[p], a.neighbor.begin() + a.offset[p + 1]);
        std::sort(got.begin(), got.end());
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(got, expected) << "particle " << p;
      }
}

// Breaks every family bond crossing the plane x = 3.5 lambda; `both` breaks it from both ends,
// otherwise only from the particle left of the plane.
BondLists cut_block(const SimulationInput& in, BondLists bonds, bool both) {
  const BondsView v = bonds.view();
  const double plane = 3.5e-3;
  for (int32_t i = 0; i < v.n; ++i) {
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
      const bool left_i = in.particles.rest[size_t(i)].x < plane,
                 left_j = in.particles.rest[size_t(j)].x < plane;
      if (left_i != left_j && (both || left_i)) bonds.neighbor[size_t(v.slot(i, k))] = ~j;
    }
  }
  return bonds;
}

TEST(Components, BlockCutByAPlaneGivesExactlyTwo) {
  const int nx = 8, ny = 6, nz = 5;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, 1e-3);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  ComponentFinder finder(
      grid_adjacency(bonds, in.particles.rest, particle_spacing(in.particles, in.materials)), bonds);
  EXPECT_EQ(finder.pairs(), size_t(3 * nx * ny * nz - (ny * nz + nx * nz + nx * ny)));

  // Intact: one component.
  Components whole;
  finder.find(bonds, whole);
  EXPECT_EQ(whole.count(), 1u);
  expect_consistent(whole);

  // Cut, from both ends or from one: particles left of the plane are fragment 0, the others
  // fragment 4 (the first particle right of it).
  for (bool both : {true, false}) {
    Components c;
    finder.find(cut_block(in, bonds, both), c);
    ASSERT_EQ(c.count(), 2u) << (both ? "both ends" : "one end");
    expect_consistent(c);
    for (size_t i = 0; i < in.particles.size(); ++i) EXPECT_EQ(c.id[i], (i % nx) < 4 ? 0 : 4) << i;
    EXPECT_EQ(c.size(0), 4 * ny * nz);
    EXPECT_EQ(c.size(1), 4 * ny * nz);
  }
}

TEST(Components, OnlyAdjacentBondsSeparate) {
  // Breaking every bond across the plane except the face bonds leaves the block whole.
  const int nx = 8, ny = 4, nz = 4;
  const SimulationInput in = testing::lattice_block(nx, ny, nz, 1e-3);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  const ElementAdjacency adj =
      grid_adjacency(bonds, in.particles.rest, particle_spacing(in.particles, in.materials));
  ComponentFinder finder(adj, bonds);
  BondLists cut = cut_block(in, bonds, true);
  for (size_t i = 0; i < adj.size(); ++i)
    for (int64_t e = adj.offset[i]; e < adj.offset[i + 1]; ++e) {
      const BondsView v = cut.view();
      for (int32_t k = 0; k < v.count[i]; ++k)
        if (cut.neighbor[size_t(v.slot(int32_t(i), k))] == ~adj.neighbor[size_t(e)])
          cut.neighbor[size_t(v.slot(int32_t(i), k))] = adj.neighbor[size_t(e)];
    }
  Components c;
  finder.find(cut, c);
  EXPECT_EQ(c.count(), 1u);
}

TEST(Components, UnionFindEqualsBreadthFirstSearchOnRandomGraphs) {
  Random rng(21);
  Components reused;
  for (int n : {1, 2, 3, 50, 1000, 20000}) {
    for (double degree : {0.5, 1.5, 4.0}) {
      // Random symmetric families; a random subset of their pairs is the adjacency.
      std::vector<std::vector<int32_t>> family(static_cast<size_t>(n));
      std::vector<std::pair<int32_t, int32_t>> pairs;
      const int64_t edges = n > 1 ? int64_t(degree * n / 2) : 0;
      for (int64_t e = 0; e < edges; ++e) {
        const int32_t a = int32_t(rng.next_u64() % uint64_t(n)), b = int32_t(rng.next_u64() % uint64_t(n));
        if (a == b ||
            std::find(family[size_t(a)].begin(), family[size_t(a)].end(), b) != family[size_t(a)].end())
          continue;
        family[size_t(a)].push_back(b);
        family[size_t(b)].push_back(a);
        if (rng.uniform() < 0.7) pairs.push_back({a, b});
      }
      BondLists bonds = bond_lists(family);
      const ElementAdjacency adj = adjacency_from_pairs(size_t(n), pairs);
      ComponentFinder finder(adj, bonds);
      // Break about a quarter of the pairs: each end on its own with probability 0.15.
      for (size_t i = 0; i < family.size(); ++i)
        for (int32_t j : family[i])
          if (rng.uniform() < 0.15) break_bond(bonds, int32_t(i), j);
      // Into a reused result: what earlier graphs left there must not leak through.
      finder.find(bonds, reused);
      const Components& c = reused;
      SCOPED_TRACE("n = " + std::to_string(n) + ", degree " + std::to_string(degree));
      EXPECT_EQ(c.id, bfs_ids(adj, bonds));
      expect_consistent(c);
    }
  }
}

TEST(Components, RejectsAdjacencyOfOtherSizeOrOneWay) {
  const BondLists bonds = bond_lists({{1}, {0, 2}, {1}});
  EXPECT_THROW(ComponentFinder(adjacency_from_pairs(4, {{0, 1}}), bonds), std::invalid_argument);
  ElementAdjacency one_way;  // 0 lists 1, 1 lists nobody
  one_way.offset = {0, 1, 1, 1};
  one_way.neighbor = {1};
  EXPECT_THROW(ComponentFinder(one_way, bonds), std::invalid_argument);
  ComponentFinder finder(adjacency_from_pairs(3, {{0, 1}}), bonds);
  Components c;
  EXPECT_THROW(finder.find(bond_lists({{1}, {0}}), c), std::invalid_argument);
}

// Touching elements farther apart than the horizon: 0 and 2 share no bond but 1 is bonded to both,
// so they stay together until a bond of that path breaks; 3 touches 0 with no bond path at all, a
// fragment of its own from the start.
TEST(Components, TouchingParticlesWithoutABondHoldThroughACommonNeighbour) {
  BondLists bonds = bond_lists({{1}, {0, 2}, {1}, {}});
  ComponentFinder finder(adjacency_from_pairs(4, {{0, 2}, {0, 3}}), bonds);
  EXPECT_EQ(finder.links().indirect(), 1u);
  EXPECT_EQ(finder.links().unlinked(), 1u);
  Components c;
  finder.find(bonds, c);
  EXPECT_EQ(c.id, (std::vector<int32_t>{0, 1, 0, 3}));
  break_bond(bonds, 2, 1);
  finder.find(bonds, c);
  EXPECT_EQ(c.id, (std::vector<int32_t>{0, 1, 2, 3}));
}

TEST(Components, FromIdsNumbersByFirstAppearance) {
  const Components c = components_from_ids({2, 1, 2, 1, 4});
  EXPECT_EQ(c.index, (std::vector<int32_t>{0, 1, 0, 1, 2}));
  EXPECT_EQ(c.start, (std::vector<int32_t>{0, 2, 4, 5}));
  EXPECT_EQ(c.members, (std::vector<int32_t>{0, 2, 1, 3, 4}));
  EXPECT_THROW(components_from_ids({0, 2}), std::invalid_argument);
  EXPECT_THROW(components_from_ids({-1}), std::invalid_argument);
}

TEST(Components, StatsAndLogLine) {
  // Sizes 1, 1, 2, 3, 5, 8.
  std::vector<int32_t> id;
  int32_t next = 0;
  for (int size : {1, 1, 2, 3, 5, 8}) {
    for (int k = 0; k < size; ++k) id.push_back(next);
    next += size;
  }
  const ComponentStats s = component_stats(components_from_ids(id));
  EXPECT_EQ(s.count, 6u);
  EXPECT_EQ(s.largest, 8);
  EXPECT_EQ(s.histogram, (std::vector<int64_t>{2, 2, 1, 1}));
  EXPECT_EQ(format_component_stats(s), "fragments 6 (1:2 2-3:2 4-7:1 8-15:1)");
  EXPECT_EQ(s.singles, 2);
  // With masses (particle k weighs k + 1 kg): the singles are particles 0 and 1, 3 kg of 210.
  std::vector<real> mass(id.size());
  for (size_t k = 0; k < mass.size(); ++k) mass[k] = real(k + 1);
  const ComponentStats m = component_stats(components_from_ids(id), mass);
  EXPECT_DOUBLE_EQ(m.mass, 210);
  EXPECT_DOUBLE_EQ(m.single_mass, 3);
  EXPECT_DOUBLE_EQ(m.largest_mass, 13 + 14 + 15 + 16 + 17 + 18 + 19 + 20);  // the last 8 particles
  EXPECT_EQ(format_component_stats(m), "fragments 6 (1:2 2-3:2 4-7:1 8-15:1) singles 1.4% of the mass");
}

// Singles against free particles: 2 shares no face with 1 but still holds by their bond (a
// diagonal one), a single that moves with its neighbour; 3 has lost its only bond, a single and free.
TEST(Components, FreeParticlesAreTheSinglesWithoutAnIntactBond) {
  BondLists bonds = bond_lists({{1}, {0, 2}, {1, 3}, {2}});
  ComponentFinder finder(adjacency_from_pairs(4, {{0, 1}, {2, 3}}), bonds);
  break_bond(bonds, 2, 3);
  break_bond(bonds, 3, 2);  // (both ends, as the engine breaks a bond)
  Components c;
  finder.find(bonds, c);
  EXPECT_EQ(c.id, (std::vector<int32_t>{0, 0, 2, 3}));
  const std::vector<real> mass = {1, 2, 3, 4};
  const ComponentStats s = component_stats(c, mass, &bonds);
  EXPECT_EQ(s.singles, 2);
  EXPECT_DOUBLE_EQ(s.single_mass, 7);
  EXPECT_TRUE(s.free_counted);
  EXPECT_DOUBLE_EQ(s.free_mass, 4);
  EXPECT_EQ(format_component_stats(s), "fragments 3 (1:2 2-3:1) singles 70.0% of the mass (free 40.0%)");
  EXPECT_FALSE(component_stats(c, mass).free_counted);
}

}  // namespace
}  // namespace pd
