// Helpers shared by the fragment tests: hand-made families in the engine's sliced-ELL layout,
// bond breaking, and a scratch directory per test.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/fragments/tet_complex.h"
#include "tests/support/temp_dir.h"

namespace pd::testing {

// Families stored as the engine stores them (slices of kSliceWidth particles, bond k of particle i
// at slice_offset[i / W] + k W + i % W), from one neighbour list per particle.
inline BondLists bond_lists(const std::vector<std::vector<int32_t>>& family) {
  const size_t n = family.size(), slices = (n + kSliceWidth - 1) / kSliceWidth;
  BondLists b;
  b.count.resize(n);
  b.slice_offset.assign(slices + 1, 0);
  for (size_t s = 0; s < slices; ++s) {
    size_t width = 0;
    for (size_t i = s * kSliceWidth; i < std::min(n, (s + 1) * kSliceWidth); ++i)
      width = std::max(width, family[i].size());
    b.slice_offset[s + 1] = b.slice_offset[s] + int64_t(width * kSliceWidth);
  }
  b.neighbor.assign(size_t(b.slice_offset.back()), 0);
  const BondsView v = b.view();
  for (size_t i = 0; i < n; ++i) {
    b.count[i] = int32_t(family[i].size());
    for (size_t k = 0; k < family[i].size(); ++k)
      b.neighbor[size_t(v.slot(int32_t(i), int32_t(k)))] = family[i][k];
  }
  return b;
}

// Marks the bond to j in i's family broken (~j); returns false when i has no bond to j.
inline bool break_bond(BondLists& b, int32_t i, int32_t j) {
  const BondsView v = b.view();
  for (int32_t k = 0; k < v.count[i]; ++k) {
    int32_t& nb = b.neighbor[size_t(v.slot(i, k))];
    if (nb == j) {
      nb = ~j;
      return true;
    }
  }
  return false;
}

// An nx x ny x nz block of cubes of side `side` from the origin, each cut into the 6 tets around
// its diagonal (Kuhn): the tets of neighbouring cubes meet face to face. Tet t is particle t.
inline EmbeddedTets box_tets(int nx, int ny, int nz, double side) {
  EmbeddedTets m;
  auto id = [&](int i, int j, int k) { return int32_t(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.vertices.push_back({i * side, j * side, k * side});
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& a : axes) {
          std::array<int, 3> c{i, j, k};
          std::array<int32_t, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[size_t(a[s])];
            t[size_t(s) + 1] = id(c[0], c[1], c[2]);
          }
          m.particle.push_back(int32_t(m.tets.size()));
          m.tets.push_back(t);
        }
  return m;
}

}  // namespace pd::testing
