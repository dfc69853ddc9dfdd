#include "adjacency.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pd {

ElementAdjacency adjacency_from_pairs(size_t n, const std::vector<std::pair<int32_t, int32_t>>& pairs) {
  // Degrees, then offsets.
  ElementAdjacency adj;
  adj.offset.assign(n + 1, 0);
  for (const auto& [a, b] : pairs) {
    if (a < 0 || b < 0 || size_t(a) >= n || size_t(b) >= n || a == b)
      throw std::invalid_argument("adjacency pair (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") is not two distinct particles of " + std::to_string(n));
    ++adj.offset[size_t(a) + 1];
    ++adj.offset[size_t(b) + 1];
  }
  for (size_t i = 0; i < n; ++i) adj.offset[i + 1] += adj.offset[i];

  // Both directions of every pair, then each list sorted and checked for repeats.
  adj.neighbor.resize(size_t(adj.offset[n]));
  std::vector<int64_t> fill(adj.offset.begin(), adj.offset.end() - 1);
  for (const auto& [a, b] : pairs) {
    adj.neighbor[size_t(fill[size_t(a)]++)] = b;
    adj.neighbor[size_t(fill[size_t(b)]++)] = a;
  }
  for (size_t i = 0; i < n; ++i) {
    auto first = adj.neighbor.begin() + adj.offset[i], last = adj.neighbor.begin() + adj.offset[i + 1];
    std::sort(first, last);
    auto repeat = std::adjacent_find(first, last);
    if (repeat != last)
      throw std::invalid_argument("adjacency pair (" + std::to_string(i) + ", " + std::to_string(*repeat) +
                                  ") is given twice");
  }
  return adj;
}

std::vector<real> particle_spacing(const ParticleSet& particles, const MaterialTable& materials) {
  std::vector<real> spacing(particles.size());
  for (size_t i = 0; i < particles.size(); ++i) spacing[i] = materials.m[particles.material[i]].spacing;
  return spacing;
}

ElementAdjacency grid_adjacency(const BondLists& bonds, const std::vector<Vec3>& rest,
                                const std::vector<real>& spacing) {
  const BondsView v = bonds.view();
  if (rest.size() != size_t(v.n) || spacing.size() != size_t(v.n))
    throw std::invalid_argument("grid_adjacency: bonds, rest positions and spacings differ in length");

  // A bond is a face bond when its rest length is within 1% of both cube sides.
  auto face_bond = [&](int32_t i, int32_t j) {
    const double r = length(rest[size_t(j)] - rest[size_t(i)]);
    const double li = spacing[size_t(i)], lj = spacing[size_t(j)];
    return std::abs(r - li) <= 0.01 * li && std::abs(r - lj) <= 0.01 * lj;
  };

  // Pass 1: face bonds per particle; pass 2: fill in family order.
  ElementAdjacency adj;
  adj.offset.assign(size_t(v.n) + 1, 0);
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < v.n; ++i) {
    int64_t faces = 0;
    for (int32_t k = 0; k < v.count[i]; ++k) faces += face_bond(i, bond_partner(v.neighbor[v.slot(i, k)]));
    adj.offset[size_t(i) + 1] = faces;
  }
  for (int32_t i = 0; i < v.n; ++i) adj.offset[size_t(i) + 1] += adj.offset[size_t(i)];
  adj.neighbor.resize(size_t(adj.offset.back()));
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < v.n; ++i) {
    int64_t at = adj.offset[size_t(i)];
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
      if (face_bond(i, j)) adj.neighbor[size_t(at++)] = j;
    }
  }
  return adj;
}

}  // namespace pd
