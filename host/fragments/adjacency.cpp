#include "host/fragments/adjacency.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pd {

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
