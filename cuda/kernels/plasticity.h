// Kernel `plasticity` (plastic state-based materials only): deviatoric return mapping of
// Mitchell 2011 as used by Chen et al. (eqs. 10-15). Trial deviatoric force state
//   t^d_j = (15 mu / m_i) omega (e^d_j - e^p_j),  e^d = e - theta_i |xi| / 3,
// yield function f = |t^d|^2 / 2 - psi_0 with |t^d|^2 = sum_j (t^d_j)^2 beta V_j; when f > 0
// the trial state is scaled onto the yield surface, e^p_j = e^d_j - s (e^d_j - e^p_j) with
// s = sqrt(2 psi_0) / |t^d|, and Chen's limit caps |e^p_j| <= gamma |xi_j| (eq. 15).
// Each particle updates only its own end's history and that end's mirror at the partner's slot
// (BondsView::plastic_mirror), so there is no race with its partners.
#pragma once

#include <cmath>

#include "state_based.h"

namespace pd {

template <bool kAnisotropic = true, bool kLattice = true>
PD_HD inline void plastic_update(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  if (!m.plastic) return;
  // The trial norm |t^d| over the intact family, summed by `init` (state_based.h: dilatation).
  const Vec4 state = p.state[i];
  const real theta = state.x, norm = state.w, yield_norm = std::sqrt(real(2) * m.yield_psi0);
  if (norm <= yield_norm) return;

  // Project onto the yield surface and cap the plastic extension.
  const real scale = yield_norm / norm;
  for_each_intact_bond<kLattice>(i, p, b, [&](int64_t slot, int32_t j, const auto& g) {
    // The mirror's slot first: its loads then overlap the update's (+3%, bench/NOTES.md).
    const int64_t mirror = b.plastic_mirror ? b.slot(j, b.reverse[slot]) : -1;
    const real ed = g.e - theta * g.r0 * real(1.0 / 3.0);
    real ep = ed - scale * (ed - b.plastic[slot]);
    if (m.plastic_limit > real(0)) {
      const real cap = m.plastic_limit * g.r0;
      ep = ep > cap ? cap : (ep < -cap ? -cap : ep);
    }
    b.plastic[slot] = ep;
    if (mirror >= 0) b.plastic_mirror[mirror] = ep;
  });
}

// The mirror of every bond end's e^p at the partner's slot, from the history (after a restore).
PD_HD inline void mirror_plastic(int32_t i, BondsView b) {
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int64_t slot = b.slot(i, k);
    b.plastic_mirror[b.slot(bond_partner(b.neighbor[slot]), b.reverse[slot])] = b.plastic[slot];
  }
}

}  // namespace pd
