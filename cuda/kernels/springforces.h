// Kernel 4, `springforces` (bond-based PMB, Silling & Askari 2005; Levine sec. 3). For each
// bond of particle i: stretch s = (|y| - |xi|)/|xi| with y = xi + (u_j - u_i); remove the
// bond when s > max(tau'_i, tau'_j) (both ends decide identically, so momentum is kept);
// record the minimum stretch for eq. 5; accumulate f_i = sum_j c s V_i V_j beta_ij y/|y|.
#pragma once

#include "bond.h"

namespace pd {

// One end's share of a PMB bond's elastic energy: the micropotential c s^2 |xi| / 2 per unit
// volume squared, halved between the two ends: c s^2 |xi| beta V_i V_j / 4.
PD_HD inline real pmb_bond_energy(real s, real r0, real vol_i, real vol_j, const Material& m) {
  return real(0.25) * m.micromodulus * s * s * r0 * volume_fraction(r0, m) * vol_i * vol_j;
}

template <bool kAccumulate>
PD_HD inline void spring_forces(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  const Vec4 rest_i = p.rest[i];
  const Vec4 disp_i = p.disp[i];
  const real tau_i = disp_i.w;
  const int32_t count = b.count[i];
  Vec3 f{0, 0, 0};
  real smin = real(0);
  int32_t intact = 0;
  PD_BOND_LOOP
  for (int32_t k = 0; k < count; ++k) {
    const int64_t slot = b.slot(i, k);
    const int32_t j = b.neighbor[slot];
    if (!bond_intact(j)) continue;
    const Vec4 rest_j = p.rest[j];
    const Vec4 disp_j = p.disp[j];
    const Vec3 xi = xyz(rest_j) - xyz(rest_i);
    const Vec3 eta = xyz(disp_j) - xyz(disp_i);
    const Vec3 y = xi + eta;
    const BondLengths l = bond_lengths(xi, y);
    const real s = bond_elongation(xi, eta, l.r0, l.r) * l.inv_r0;
    const real tau_j = disp_j.w;
    if (s > (tau_i > tau_j ? tau_i : tau_j)) {
      b.neighbor[slot] = ~j;
      p.ledger[i].released += double(pmb_bond_energy(s, l.r0, rest_i.w, rest_j.w, m));
      continue;
    }
    smin = (intact == 0 || s < smin) ? s : smin;
    ++intact;
    f += (m.micromodulus * s * rest_j.w * volume_fraction(l.r0, m) * l.inv_r) * y;
  }
  f = rest_i.w * f;
  p.force[i] = kAccumulate ? p.force[i] + f : f;
  p.strain_min[i] = smin;
  p.intact[i] = intact;
}

}  // namespace pd
