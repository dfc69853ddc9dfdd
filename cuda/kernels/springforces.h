// Kernel 4, `springforces` (bond-based PMB, Silling & Askari 2005; Levine sec. 3). For each
// bond of particle i: stretch s = (|y| - |xi|)/|xi| with y = xi + (u_j - u_i); remove the
// bond when s > w max(tau'_i, tau'_j) (w the bond's strength, 1 unless the scene weakens
// bonds; both ends decide identically, so momentum is kept);
// record the minimum stretch for eq. 5; accumulate f_i = sum_j c s V_i V_j beta_ij y/|y|.
#pragma once

#include <cmath>

#include "bond.h"

namespace pd {

// One end's share of a PMB bond's elastic energy: the micropotential c s^2 |xi| / 2 per unit
// volume squared, halved between the two ends: c s^2 |xi| beta V_i V_j / 4 (weight_j = beta V_j).
PD_HD inline real pmb_bond_energy(real s, real r0, real vol_i, real weight_j, const Material& m) {
  return real(0.25) * m.micromodulus * s * s * r0 * vol_i * weight_j;
}

template <bool kWeak, bool kLattice = true>
PD_HD inline void spring_forces(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  const real vol_i = p.volume(i), tau_i = p.strain_limit(i);
  Vec3 f{0, 0, 0};  // sum over the intact bonds of s beta V_j y/|y| (c V_i applied once at the end)
  real smin = real(INFINITY);
  // The entry loop unrolled 8 times where bonds may be weakened, as the compiler picks (2) else
  // (bench/NOTES.md: each the faster of the two for its kernel).
  constexpr int kUnroll = kWeak ? 8 : 2;
  const int32_t intact =
      for_each_intact_bond<kLattice, kUnroll>(i, p, b, [&](int64_t slot, int32_t, const auto& g) {
        const real s = g.e * g.inv_r0;
        if (s > max_of(tau_i, g.tau_j) * bond_strength<kWeak>(b, slot, g)) {
          p.ledger[i].released += double(pmb_bond_energy(s, g.r0, vol_i, g.weight(m), m));
          return false;  // broken: for_each_intact_bond records it
        }
        smin = min_of(s, smin);
        f += (s * g.weight(m) * g.inv_r) * g.y;
        return true;
      });
  f = (m.micromodulus * vol_i) * f;
  p.force[i] = f;
  p.strain_min[i] = intact > 0 ? smin : real(0);
  p.intact[i] = intact;
}

}  // namespace pd
