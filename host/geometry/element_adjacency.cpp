#include "host/geometry/element_adjacency.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pd {

ElementAdjacency adjacency_from_pairs(size_t n, std::vector<std::pair<int32_t, int32_t>> pairs) {
  for (const auto& [a, b] : pairs)
    if (a < 0 || b < 0 || size_t(a) >= n || size_t(b) >= n || a == b)
      throw std::invalid_argument("adjacency pair (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") is not two distinct particles of " + std::to_string(n));
  // Both directions, bucketed by the first entry (a counting sort), each row sorted, repeats
  // dropped.
  ElementAdjacency adj;
  std::vector<int64_t> start(n + 1, 0);
  for (const auto& [a, b] : pairs) {
    ++start[size_t(a) + 1];
    ++start[size_t(b) + 1];
  }
  for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int32_t> all(size_t(start[n]));
  {
    std::vector<int64_t> fill(start.begin(), start.end() - 1);
    for (const auto& [a, b] : pairs) {
      all[size_t(fill[size_t(a)]++)] = b;
      all[size_t(fill[size_t(b)]++)] = a;
    }
  }
  pairs = {};
  adj.offset.assign(n + 1, 0);
  adj.neighbor.reserve(all.size());
  for (size_t i = 0; i < n; ++i) {
    const auto row = all.begin() + start[i], row_end = all.begin() + start[i + 1];
    std::sort(row, row_end);
    adj.neighbor.insert(adj.neighbor.end(), row, std::unique(row, row_end));
    adj.offset[i + 1] = int64_t(adj.neighbor.size());
  }
  return adj;
}

}  // namespace pd
