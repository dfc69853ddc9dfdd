// Kernel 5, `plasticity` (plastic state-based materials only): deviatoric return mapping of
// Mitchell 2011 as used by Chen et al. (eqs. 10-15). Trial deviatoric force state
//   t^d_j = (15 mu / m_i) omega (e^d_j - e^p_j),  e^d = e - theta_i |xi| / 3,
// yield function f = |t^d|^2 / 2 - psi_0 with |t^d|^2 = sum_j (t^d_j)^2 beta V_j; when f > 0
// the trial state is scaled onto the yield surface, e^p_j = e^d_j - s (e^d_j - e^p_j) with
// s = sqrt(2 psi_0) / |t^d|, and Chen's limit caps |e^p_j| <= gamma |xi_j| (eq. 15).
// The work is split where the data is read: `init` sums |t^d| over the bonds (state_based.h),
// this kernel makes the yield test per particle and keeps s in the particle's state (1: no
// flow), and `springforces` moves both ends' e^p of each bond onto the surface as it reads
// them (springforces_state.h), own end at its slot and the partner's end at the mirror: the
// two threads of a bond compute the same bits for each end, so no thread writes another's
// slots and the history is walked once per step (bench/NOTES.md).
#pragma once

#include <cmath>

#include "cuda/kernels/family.h"
#include "cuda/kernels/state_based.h"

namespace pd {

// The return mapping's factor s for a trial norm |t^d|: below 1 when the particle yields, else 1.
PD_HD inline real yield_scale(real trial_norm, const Material& m) {
  const real yield_norm = std::sqrt(real(2) * m.yield_psi0);
  return trial_norm > yield_norm ? yield_norm / trial_norm : real(1);
}

// One bond end's plastic extension after the return mapping with factor scale (< 1), from its
// extension e, |xi|, the end particle's theta and its e^p before this step.
PD_HD inline real returned_plastic_extension(real e, real r0, real theta, real scale, real ep,
                                             const Material& m) {
  const real ed = e - theta * r0 * real(1.0 / 3.0);
  real out = ed - scale * (ed - ep);
  if (m.plastic_limit > real(0)) {
    const real cap = m.plastic_limit * r0;
    out = out > cap ? cap : (out < -cap ? -cap : out);
  }
  return out;
}

// Per particle: the trial norm `init` left in state.w becomes the factor s; a particle that has
// never flowed (its norm's sign bit set by `init`) and does not flow now gets +infinity instead
// of 1 (reads_plastic_history, state_based.h).
PD_HD inline void yield_test(int32_t i, ParticlesView p, const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  if (!m.plastic) return;
  const real trial = p.state[i].w, scale = yield_scale(std::fabs(trial), m);
  p.state[i].w = std::signbit(trial) && scale == real(1) ? real(INFINITY) : scale;
}

// The mirror of every bond end's e^p at the partner's slot, from the history (after a restore).
PD_HD inline void mirror_plastic(int32_t i, BondsView b) {
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int64_t slot = b.slot(i, k);
    const int32_t j = bond_partner(b.neighbor[slot]), q = position_in_family(b, j, i);
    if (q >= 0) b.plastic_mirror[b.slot(j, q)] = b.plastic[slot];  // families are symmetric: always
  }
}

}  // namespace pd
