// Kernel 1, `init`: load the strain limits for this step (Levine eq. 5; for bond-based materials
// with a damage factor, raised by the particle's damage as Chen eq. 18 raises it), and for state-based
// materials compute the damage phi_i and the dilatation theta_i at the new positions (Chen
// eqs. 5, 18), which `springforces` reads from both ends, and for plastic materials the trial
// deviatoric norm that `plasticity` tests.
#pragma once

#include "cuda/kernels/state_based.h"
#include "cuda/views.h"

namespace pd {

// tau'_i = tau_i - alpha * min(0, eps_min_i), eps_min_i from the previous force pass.
PD_HD inline real effective_strain_limit(real tau0, real alpha, real strain_min) {
  return tau0 - alpha * (strain_min < real(0) ? strain_min : real(0));
}

// A bond-based particle's limit raised by its damage phi_i = 1 - intact/initial bonds of the last
// force pass: tau'_i (1 + alpha phi_i), Chen eq. 18's factor (state_based.h) on Levine's limit.
// A particle losing bonds holds its last ones longer, so fewer end as single-particle dust; the
// bond test max(tau_i, tau_j) stays symmetric. alpha = 0 leaves the limit's bits as they are.
PD_HD inline real damaged_strain_limit(real limit, int32_t i, ParticlesView p, BondsView b,
                                       const Material& m) {
  if (!(m.damage_alpha > real(0)) || b.count[i] == 0) return limit;
  const real damage = real(1) - real(p.intact[i]) / real(b.count[i]);
  return limit * (real(1) + m.damage_alpha * damage);
}

// A team (team.h) sums theta_i over its lanes; its leader writes.
template <bool kStateBased, bool kAnisotropic, int kLattice = kLatticeListed, bool kPlastic = false,
          int kThreads = 1>
PD_HD inline void init_particle(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                const Team<kThreads>& team = {}) {
  const Material& m = mt.m[p.material[i]];
  const real limit = effective_strain_limit(p.strain_limit0[i], m.compression_alpha, p.strain_min[i]);
  if (team.leader()) p.disp[i].w = kStateBased ? limit : damaged_strain_limit(limit, i, p, b, m);
  if constexpr (kStateBased) {
    const int32_t count = b.count[i];
    const DilatationPass d = dilatation<kAnisotropic, kLattice, kPlastic>(i, p, b, m, team);
    if (!team.leader()) return;
    Vec4 s = p.state[i];
    s.x = d.theta;
    s.z = count > 0 ? real(1) - real(p.intact[i]) / real(count) : real(0);
    if constexpr (kPlastic) s.w = d.trial_norm;
    p.state[i] = s;
  }
}

}  // namespace pd
