#include "face_links.h"

#include <stdexcept>
#include <string>

namespace pd {

namespace {

// Slot of the bond to j in i's family; -1 when there is none.
int64_t bond_slot(const BondsView& v, int32_t i, int32_t j) {
  for (int32_t k = 0; k < v.count[i]; ++k)
    if (bond_partner(v.neighbor[v.slot(i, k)]) == j) return v.slot(i, k);
  return -1;
}

}  // namespace

FaceLinks::FaceLinks(const std::vector<std::array<int32_t, 2>>& pairs, const BondLists& bonds) {
  const BondsView v = bonds.view();
  start_.reserve(pairs.size() + 1);
  slot_.reserve(2 * pairs.size());
  for (const auto& [a, b] : pairs) {
    if (a < 0 || b < 0 || a >= v.n || b >= v.n)
      throw std::invalid_argument("FaceLinks: pair (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") outside the families of " + std::to_string(v.n) + " particles");
    const int64_t ab = bond_slot(v, a, b), ba = bond_slot(v, b, a);
    direct_.push_back(ab >= 0 && ba >= 0);
    if (direct_.back()) {
      slot_.push_back(ab);
      slot_.push_back(ba);
    } else {
      // No direct bond: every common neighbour j bonded both ways to both gives a link.
      const size_t before = slot_.size();
      for (int32_t k = 0; k < v.count[a]; ++k) {
        const int32_t j = bond_partner(v.neighbor[v.slot(a, k)]);
        const int64_t ja = bond_slot(v, j, a), bj = bond_slot(v, b, j), jb = bond_slot(v, j, b);
        if (ja < 0 || bj < 0 || jb < 0) continue;
        slot_.insert(slot_.end(), {v.slot(a, k), ja, bj, jb});
      }
      ++(slot_.size() > before ? indirect_ : unlinked_);
    }
    start_.push_back(int64_t(slot_.size()));
  }
}

}  // namespace pd
