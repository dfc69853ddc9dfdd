// Kernel 1, `init`: load the strain limits for this step (Levine eq. 5) and empty the
// collision hash bins.
#pragma once

#include "../views.h"

namespace pd {

// tau'_i = tau_i - alpha * min(0, eps_min_i), eps_min_i from the previous force pass.
PD_HD inline real effective_strain_limit(real tau0, real alpha, real strain_min) {
  return tau0 - alpha * (strain_min < real(0) ? strain_min : real(0));
}

PD_HD inline void init_particle(int32_t i, ParticlesView p, const MaterialTable& mt) {
  const real alpha = mt.m[p.material[i]].compression_alpha;
  p.strain_limit[i] = effective_strain_limit(p.strain_limit0[i], alpha, p.strain_min[i]);
}

PD_HD inline void reset_bin(uint32_t b, HashView h) {
  h.bin_start[b] = -1;
  h.bin_end[b] = -1;
}

}  // namespace pd
