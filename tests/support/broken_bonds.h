// The broken bonds of an engine's families as (particle, partner) pairs, and how two such sets
// agree (the Jaccard index): how the GPU suites compare runs whose cracks may differ by round-off.
#pragma once

#include <cstdint>
#include <set>
#include <utility>

#include "cuda/engine/engine.h"

namespace pd::testing {

using BondSet = std::set<std::pair<int32_t, int32_t>>;

inline BondSet broken_bond_set(Engine& e) {
  BondLists lists;
  e.read_bonds(lists);
  const BondsView v = lists.view();
  BondSet broken;
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k)
      if (!bond_intact(v.neighbor[v.slot(i, k)])) broken.insert({i, bond_partner(v.neighbor[v.slot(i, k)])});
  return broken;
}

// |a and b| / |a or b|.
inline double jaccard(const BondSet& a, const BondSet& b) {
  size_t common = 0;
  for (const auto& bond : a) common += b.count(bond);
  return double(common) / double(a.size() + b.size() - common);
}

}  // namespace pd::testing
