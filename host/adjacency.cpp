#include "adjacency.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pd {

ElementAdjacency adjacency_from_pairs(size_t n, std::vector<std::pair<int32_t, int32_t>> pairs) {
  for (const auto& [a, b] : pairs)
    if (a < 0 || b < 0 || size_t(a) >= n || size_t(b) >= n || a == b)
      throw std::invalid_argument("adjacency pair (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") is not two distinct particles of " + std::to_string(n));
  // Both directions, sorted, repeats dropped; the rows follow from the first entries.
  const size_t m = pairs.size();
  pairs.reserve(2 * m);
  for (size_t k = 0; k < m; ++k) pairs.emplace_back(pairs[k].second, pairs[k].first);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  ElementAdjacency adj;
  adj.offset.assign(n + 1, 0);
  for (const auto& [a, b] : pairs) ++adj.offset[size_t(a) + 1];
  for (size_t i = 0; i < n; ++i) adj.offset[i + 1] += adj.offset[i];
  adj.neighbor.reserve(pairs.size());
  for (const auto& [a, b] : pairs) adj.neighbor.push_back(b);
  return adj;
}

}  // namespace pd
