#include "cuda/engine/particle_set.h"

#include <algorithm>

#include "cuda/kernels/family.h"

namespace pd {

void ParticleSet::reserve(size_t n) {
  rest.reserve(n);
  velocity.reserve(n);
  volume.reserve(n);
  mass.reserve(n);
  strain_limit0.reserve(n);
  material.reserve(n);
  body.reserve(n);
  flags.reserve(n);
  anchor.reserve(n);
}

size_t ParticleSet::add(Vec3 x, Vec3 v, real vol, real m, real tau0, uint16_t mat, int32_t body_id,
                        uint8_t flag_bits, uint8_t anchor_group) {
  rest.push_back(x);
  velocity.push_back(v);
  volume.push_back(vol);
  mass.push_back(m);
  strain_limit0.push_back(tau0);
  material.push_back(mat);
  body.push_back(body_id);
  flags.push_back(flag_bits);
  anchor.push_back(anchor_group);
  return rest.size() - 1;
}

double longest_bond_bound(const ParticleSet& ps, const MaterialTable& mt) {
  double radius = 0, extent = 0;
  for (int m = 0; m < mt.count; ++m) radius = std::max(radius, double(mt.m[m].family_radius()));
  for (const Vec3& x : ps.rest) extent = std::max(extent, largest_coordinate(x));
  return radius * (1.0 + 1e-4) + 2 * kPositionSlack * extent;
}

}  // namespace pd
