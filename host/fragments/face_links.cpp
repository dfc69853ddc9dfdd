#include "host/fragments/face_links.h"

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
  for (const auto& [a, b] : pairs)
    if (a < 0 || b < 0 || a >= v.n || b >= v.n)
      throw std::invalid_argument("FaceLinks: pair (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") outside the families of " + std::to_string(v.n) + " particles");
  // The direct bond of every pair, both ways (a search through each family: in parallel).
  const int64_t np = int64_t(pairs.size());
  std::vector<std::array<int64_t, 2>> direct(pairs.size());
#pragma omp parallel for schedule(static)
  for (int64_t p = 0; p < np; ++p) {
    const auto [a, b] = pairs[size_t(p)];
    direct[size_t(p)] = {bond_slot(v, a, b), bond_slot(v, b, a)};
  }
  start_.reserve(pairs.size() + 1);
  slot_.reserve(2 * pairs.size());
  direct_.reserve(pairs.size());
  for (size_t p = 0; p < pairs.size(); ++p) {
    const auto [a, b] = pairs[p];
    const auto [ab, ba] = direct[p];
    direct_.push_back(ab >= 0 && ba >= 0);
    if (direct_.back()) {
      slot_.push_back(ab);
      slot_.push_back(ba);
    } else {
      // No direct bond (rare): every common neighbour j bonded both ways to both gives a link.
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
