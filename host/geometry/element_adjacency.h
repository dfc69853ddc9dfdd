// Element adjacency: which particles' geometric elements touch (cube faces, tet faces, Voronoi
// facets). The geometry stage builds it; its unbroken part splits a body into fragments
// (Levine sec. 4), a subset of the family bonds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pd {

// Symmetric neighbour lists in CSR form: the elements adjacent to particle i are
// neighbor[offset[i] .. offset[i + 1]), sorted; j is listed for i exactly when i is listed for j.
struct ElementAdjacency {
  std::vector<int64_t> offset{0};  // particles + 1 entries
  std::vector<int32_t> neighbor;

  size_t size() const { return offset.size() - 1; }
  int64_t degree(size_t i) const { return offset[i + 1] - offset[i]; }
};

// From unordered pairs (either order; a pair given twice counts once): both directions, each
// list sorted. Throws std::invalid_argument for an index outside [0, n) or a self pair.
ElementAdjacency adjacency_from_pairs(size_t n, std::vector<std::pair<int32_t, int32_t>> pairs);

}  // namespace pd
