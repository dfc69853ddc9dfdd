#include "cuda/engine/particle_set.h"

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

}  // namespace pd
