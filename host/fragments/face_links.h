// What holds two face-adjacent elements together (Chen sec. 5.2: a face cracks when its bond
// breaks). Normally that is the bond between their particles, intact in both families. Where the
// particles of two touching elements are farther apart than the horizon (a coarse delta/lambda on
// irregular cells: tets of mixed sizes, Voronoi cells at delta = 2 lambda), there is no such bond;
// the pair is then held by the bonds through their common neighbours, and holds while, for some
// particle j bonded to both, the bonds a-j and b-j are intact in all four families' copies. A pair with
// neither is a crack from the start (counted, so the scene set-up can say so).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cuda/engine/engine.h"

namespace pd {

class FaceLinks {
 public:
  // `pairs`: element pairs (a, b), particle indices of the families `bonds`. Throws
  // std::invalid_argument for an index outside the families.
  FaceLinks() = default;
  FaceLinks(const std::vector<std::array<int32_t, 2>>& pairs, const BondLists& bonds);

  // Whether pair p still holds, with `neighbor` the families' neighbour array as the engine holds
  // it now (the same layout as at construction).
  bool intact(size_t p, const int32_t* neighbor) const {
    const int64_t width = direct_[p] ? 2 : 4;
    for (int64_t k = start_[p]; k < start_[p + 1]; k += width) {
      bool all = true;
      for (int64_t s = k; s < k + width; ++s) all = all && bond_intact(neighbor[slot_[size_t(s)]]);
      if (all) return true;
    }
    return false;
  }

  bool linked(size_t p) const { return start_[p + 1] > start_[p]; }
  size_t size() const { return start_.size() - 1; }
  size_t indirect() const { return indirect_; }  // pairs held through common neighbours
  size_t unlinked() const { return unlinked_; }  // pairs with no bond path: cracks from the start

 private:
  // The slots of pair p: slot_[start_[p] .. start_[p + 1]), in links of bond slots that must all
  // be intact: two (a-b, b-a) for a bonded pair, four (a-j, j-a, b-j, j-b) per common neighbour.
  std::vector<int64_t> start_{0};
  std::vector<int64_t> slot_;
  std::vector<uint8_t> direct_;  // per pair: bonded directly
  size_t indirect_ = 0, unlinked_ = 0;
};

}  // namespace pd
