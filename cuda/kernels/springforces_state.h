// Kernel 4, `springforces`, for state-based materials (Chen et al. eqs. 1-18). For each
// intact bond: the force states of both ends, t_ij (theta_i, m_i, e^p_ij) and t_ji (theta_j,
// m_j, e^p_ji), so f_i = V_i sum_j (t_ij + t_ji) beta V_j y/|y|; breaking by Chen's
// criterion (eq. 18) evaluated for both ends: the bond is removed when both ends' s^omega
// exceed their limits, which both threads decide from the same numbers (or, with the
// stretch criterion, when e/|xi| > max(tau_i, tau_j) as for bond-based materials). A weakened
// bond's limits are scaled by its strength w. Plastic materials: both ends' e^p first move
// onto the yield surface where the particle yields (the return mapping, plasticity.h).
#pragma once

#include "cuda/kernels/bond_screen.h"
#include "cuda/kernels/plasticity.h"
#include "cuda/kernels/state_based.h"

namespace pd {

// One pass over the bonds of particle i. kBreaking: the breaking pass (bonds past Chen's
// criterion removed); else the screened pass (bond_screen.h), which returns false where a break
// is not ruled out, having written nothing but the plastic history. kProject: move both ends'
// e^p onto the yield surface (a breaking pass after a screened one reads them moved). A team
// (team.h) sums its lanes' shares and decides on the team's sums; its leader writes.
template <bool kPlastic, bool kAnisotropic, bool kWeak, int kLattice, bool kBreaking, bool kProject,
          int kThreads>
PD_HD inline bool state_force_pass(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                   int32_t* broke, const Team<kThreads>& team) {
  const Material& m = mt.m[p.material[i]];  // both ends share it: bonds stay inside a body
  const Vec4 state_i = p.state[i];
  const real theta_i = state_i.x, inv_mw_i = state_i.y;
  const ForceStateCoefficients k_i = force_state_coefficients(theta_i, inv_mw_i, m);
  const bool flows = kPlastic && kProject && m.plastic;  // state.w holds the return mapping's factor
  const bool history_i = kPlastic && reads_plastic_history(state_i, m);
  // The particle's volume and limits: the breaking pass (and a screened pass of weakened bonds, its
  // limits) uses them in the loop; the screened pass reads them after it rather than hold them over
  // a loop whose stores keep the compiler from loading them late (bench/NOTES.md: Chen's stretch
  // tear's screened pass 9% faster, the plastic wall's 3%).
  constexpr bool kLimitsInLoop = kBreaking || kWeak;
  const real vol_i = kBreaking ? p.volume(i) : real(0);
  real tau_i = 0, limit_i = 0, own_limit = 0;  // own_limit: the screened pass's L
  auto read_limits = [&] {
    tau_i = p.strain_limit(i);
    limit_i = chen_extension_limit(tau_i, p.state[i].z, m);
    own_limit = m.chen_fracture ? limit_i : tau_i;
  };
  if constexpr (kLimitsInLoop) read_limits();
  Vec3 f{0, 0, 0};
  real smin = real(INFINITY);
  real nearest = -real(INFINITY);  // screened pass: the largest own-end margin (bond_screen.h)
  ReleasedEnergy<kThreads> released;
  const uint16_t* row = surface_row_of(b, i);
  // The partial-volume rule taken once (bond.h PartialVolumes) in the elastic pass: the explicit
  // state-based lattice's springforces +3%; the plastic pass, at its 64 registers, lost 7% in a
  // variant that took it too, and keeps the per-bond form (bench/NOTES.md, 2026-11-29).
  const PartialVolumes volumes = partial_volumes_of(m);
  // The entry loop unrolled 8 times: +3% (elastic) to +8% (plastic) against the compiler's 2
  // (bench/NOTES.md); a plastic run's histories of both ends fetched ahead.
  constexpr int kHistory = kPlastic ? kBothHistories : kNoHistory;
  // The listed loop's walk (bond.h ListedWalk): the plastic pass's from the family's base (with
  // weakened bonds clamped), the elastic pass's branched (as measured).
  constexpr int kWalk = !kPlastic ? kWalkBranched : kWeak ? kWalkClamped : kWalkFromBase;
  const int32_t intact = for_each_intact_bond<kLattice, 8, kHistory, false, kWalk>(
      i, p, b, team,
      [&](int64_t slot, int32_t j, const auto& g) {
        const Vec4 state_j = p.state[j];
        real ep_ij = kPlastic ? plastic_at(b.plastic, slot, history_i, g) : real(0);
        real ep_ji =
            kPlastic ? plastic_at(b.plastic_mirror, slot, reads_plastic_history(state_j, m), g) : real(0);
        if (flows && state_i.w < real(1)) {
          ep_ij = returned_plastic_extension(g.e, g.r0, theta_i, state_i.w, ep_ij, m);
          b.plastic[slot] = ep_ij;
        }
        if (flows && state_j.w < real(1)) {
          ep_ji = returned_plastic_extension(g.e, g.r0, state_j.x, state_j.w, ep_ji, m);
          b.plastic_mirror[slot] = ep_ji;
        }
        const real s = g.e * g.inv_r0;
        const real w = bond_strength<kWeak>(b, slot, g);
        const real tau_j = g.tau_j;
        if constexpr (kBreaking) {
          const bool breaks =
              m.chen_fracture
                  ? g.e - ep_ij > w * limit_i && g.e - ep_ji > w * chen_extension_limit(tau_j, state_j.z, m)
                  : s > max_of(tau_i, tau_j) * w;
          if (breaks) {
            released.add(
                p, i,
                double(lps_bond_energy(g, theta_i, inv_mw_i, ep_ij, vol_i, m, surface_bond_at(b, slot))));
            if (kRaiseInBranch<kWeak>) raise_flag(broke);
            return false;  // broken: for_each_intact_bond records it
          }
        } else {
          const real own = m.chen_fracture ? g.e - ep_ij : s;
          nearest = max_of(nearest, kWeak ? own - w * own_limit : own);
        }
        smin = min_of(s, smin);
        const ForceStateCoefficients k_j = force_state_coefficients(state_j.x, state_j.y, m);
        const real t = influence<kAnisotropic>(g.xi, g.inv_r0, m) * surface_factor_of(b, slot, g, row) *
                       ((k_i.a + k_j.a) * g.e - (k_i.a * ep_ij + k_j.a * ep_ji) + (k_i.c + k_j.c) * g.r0);
        f += (t * (kPlastic ? g.weight(m) : g.weight(volumes)) * g.inv_r) * g.y;
        return true;
      },
      history_i);
  if constexpr (!kLimitsInLoop) read_limits();
  if (!kBreaking && may_break<kWeak>(team.max(nearest), own_limit)) return false;
  if constexpr (kBreaking) released.settle(p, i, team);
  write_bond_forces(i, p, (kBreaking ? vol_i : p.volume(i)) * team.sum(f), team.min(smin), intact,
                    kBreaking && !kRaiseInBranch<kWeak> ? broke : nullptr, team);
  return true;
}

// The breaking pass, and the screened pass with the breaking pass where it cannot rule a break out.
template <bool kPlastic, bool kAnisotropic, bool kWeak, int kLattice = kLatticeListed, int kThreads = 1>
PD_HD inline void state_forces(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                               int32_t* broke, const Team<kThreads>& team = {}) {
  state_force_pass<kPlastic, kAnisotropic, kWeak, kLattice, true, true>(i, p, b, mt, broke, team);
}

template <bool kPlastic, bool kAnisotropic, bool kWeak, int kLattice = kLatticeListed, int kThreads = 1>
PD_HD inline void screened_state_forces(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                        int32_t* broke, const Team<kThreads>& team = {}) {
  if (!state_force_pass<kPlastic, kAnisotropic, kWeak, kLattice, false, true>(i, p, b, mt, broke, team))
    state_force_pass<kPlastic, kAnisotropic, kWeak, kLattice, true, false>(i, p, b, mt, broke, team);
}

}  // namespace pd
