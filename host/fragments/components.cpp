#include "host/fragments/components.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace pd {

namespace {

// Counting sort of the particles by component number into start/members, stable so members stay
// ascending. Storage of `c` is reused; start is first the fill cursor, then shifted back.
void group_members(Components& c, int32_t count) {
  c.start.assign(size_t(count) + 1, 0);
  for (int32_t k : c.index) ++c.start[size_t(k) + 1];
  std::partial_sum(c.start.begin(), c.start.end(), c.start.begin());
  c.members.resize(c.index.size());
  for (size_t i = 0; i < c.index.size(); ++i) c.members[size_t(c.start[size_t(c.index[i])]++)] = int32_t(i);
  for (size_t k = size_t(count); k > 0; --k) c.start[k] = c.start[k - 1];
  c.start[0] = 0;
}

}  // namespace

Components components_from_ids(std::vector<int32_t> id) {
  const size_t n = id.size();
  Components c;
  // Component numbers in order of first appearance.
  std::vector<int32_t> number(n, -1);
  c.index.resize(n);
  int32_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (id[i] < 0 || size_t(id[i]) >= n)
      throw std::invalid_argument("component id " + std::to_string(id[i]) + " of particle " +
                                  std::to_string(i) + " is outside [0, " + std::to_string(n) + ")");
    int32_t& k = number[size_t(id[i])];
    if (k < 0) k = count++;
    c.index[i] = k;
  }
  c.id = std::move(id);
  group_members(c, count);
  return c;
}

namespace {

// The undirected pairs a < b of a symmetric adjacency. Throws std::invalid_argument where it is not
// symmetric or does not cover n particles.
std::vector<std::array<int32_t, 2>> undirected_pairs(const ElementAdjacency& adjacency, size_t n) {
  if (adjacency.size() != n)
    throw std::invalid_argument("element adjacency has " + std::to_string(adjacency.size()) +
                                " particles, the families " + std::to_string(n));
  const auto& off = adjacency.offset;
  const auto& nb = adjacency.neighbor;
  std::vector<std::array<int32_t, 2>> pairs;
  for (size_t i = 0; i < n; ++i)
    for (int64_t e = off[i]; e < off[i + 1]; ++e) {
      const int32_t j = nb[size_t(e)];
      if (size_t(j) <= i) continue;
      int64_t back = off[size_t(j)];
      while (back < off[size_t(j) + 1] && size_t(nb[size_t(back)]) != i) ++back;
      if (back == off[size_t(j) + 1])
        throw std::invalid_argument("element adjacency is not symmetric: " + std::to_string(j) +
                                    " is adjacent to " + std::to_string(i) + " but not the reverse");
      pairs.push_back({int32_t(i), j});
    }
  return pairs;
}

}  // namespace

ComponentFinder::ComponentFinder(const ElementAdjacency& adjacency, const BondLists& bonds)
    : n_(bonds.count.size()),
      slots_(bonds.neighbor.size()),
      pairs_(undirected_pairs(adjacency, bonds.count.size())),
      links_(pairs_, bonds) {}

void ComponentFinder::find(const BondLists& bonds, Components& out) {
  if (bonds.count.size() != n_ || bonds.neighbor.size() != slots_)
    throw std::invalid_argument("ComponentFinder::find: the families differ from those it was built for");
  const int32_t* nb = bonds.neighbor.data();

  // Which pairs are still bonded from both ends (independent reads, in parallel).
  const int64_t pairs = int64_t(pairs_.size());
  intact_.resize(size_t(pairs));
#pragma omp parallel for schedule(static)
  for (int64_t p = 0; p < pairs; ++p) intact_[size_t(p)] = links_.intact(size_t(p), nb);

  // Union-find with path halving; the larger root is linked under the smaller, so every parent
  // index is below its child and each root is the smallest particle of its set.
  parent_.resize(n_);
  std::iota(parent_.begin(), parent_.end(), 0);
  auto root = [&](int32_t x) {
    while (parent_[size_t(x)] != x) x = parent_[size_t(x)] = parent_[size_t(parent_[size_t(x)])];
    return x;
  };
  for (int64_t p = 0; p < pairs; ++p) {
    if (!intact_[size_t(p)]) continue;
    const int32_t ra = root(pairs_[size_t(p)][0]), rb = root(pairs_[size_t(p)][1]);
    if (ra < rb) parent_[size_t(rb)] = ra;
    if (rb < ra) parent_[size_t(ra)] = rb;
  }

  // Ids and component numbers in one ascending pass: a parent's are final before its children
  // are reached, and a component first appears at its root.
  out.id.resize(n_);
  out.index.resize(n_);
  int32_t count = 0;
  for (size_t i = 0; i < n_; ++i) {
    const bool is_root = parent_[i] == int32_t(i);
    out.id[i] = is_root ? int32_t(i) : out.id[size_t(parent_[i])];
    out.index[i] = is_root ? count++ : out.index[size_t(parent_[i])];
  }
  group_members(out, count);
}

ComponentStats component_stats(const Components& c, const std::vector<real>& mass, const BondLists* bonds) {
  ComponentStats s;
  s.count = c.count();
  for (size_t k = 0; k < c.count(); ++k) {
    const int32_t size = c.size(k);
    s.largest = std::max(s.largest, size);
    s.singles += size == 1;
    size_t bin = 0;
    while ((int64_t(2) << bin) <= size) ++bin;
    if (s.histogram.size() <= bin) s.histogram.resize(bin + 1, 0);
    ++s.histogram[bin];
    if (mass.empty()) continue;
    double m = 0;
    for (int32_t j = c.start[k]; j < c.start[k + 1]; ++j) m += double(mass[size_t(c.members[size_t(j)])]);
    s.mass += m;
    if (size == 1) s.single_mass += m;
    s.largest_mass = std::max(s.largest_mass, m);
  }
  if (bonds && !mass.empty()) {
    const BondsView b = bonds->view();
    s.free_counted = true;
    for (int32_t i = 0; i < b.n; ++i) {
      bool held = false;
      for (int32_t k = 0; k < b.count[i] && !held; ++k) held = bond_intact(b.neighbor[b.slot(i, k)]);
      if (!held) s.free_mass += double(mass[size_t(i)]);
    }
  }
  return s;
}

std::string format_component_stats(const ComponentStats& s) {
  std::string out = "fragments " + std::to_string(s.count) + " (";
  bool first = true;
  for (size_t b = 0; b < s.histogram.size(); ++b) {
    if (s.histogram[b] == 0) continue;
    const int64_t lo = int64_t(1) << b, hi = (int64_t(2) << b) - 1;
    out += (first ? "" : " ") + std::to_string(lo) + (lo == hi ? "" : "-" + std::to_string(hi)) + ":" +
           std::to_string(s.histogram[b]);
    first = false;
  }
  out += ")";
  if (s.mass > 0) {
    char share[48];
    std::snprintf(share, sizeof share, " singles %.1f%% of the mass", 100 * s.single_mass / s.mass);
    out += share;
    if (s.free_counted) {
      std::snprintf(share, sizeof share, " (free %.1f%%)", 100 * s.free_mass / s.mass);
      out += share;
    }
  }
  return out;
}

}  // namespace pd
