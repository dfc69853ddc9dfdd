// Ordinary state-based linear peridynamic solid (Silling et al. 2007, "LPS"; Chen et al.
// sec. 4), shared by `init`, `plasticity` and `springforces`.
//
// Scalar force state of particle i on bond xi (e = |y| - |xi| the extension):
//   t = omega [ (3 K theta_i / m_i) |xi| + (15 mu / m_i) (e - theta_i |xi| / 3 - e^p) ]
//   theta_i = (3 / m_i) sum_j omega |xi| e beta V_j,  m_i = sum_j omega |xi|^2 beta V_j
// with omega = delta / |G xi| (Chen eqs. 4, 16) and beta the partial-volume fraction.
// The deviatoric term equals Chen's 1/2 A_dev with b = 15 mu / (2 pi delta^5) when m takes
// its continuum value pi delta^5 (Chen eq. 9); m is summed over the discrete family instead,
// which makes theta exact for any homogeneous deformation of a symmetric family.
// Force on i: f_i = V_i sum_j (t_ij + t_ji) beta V_j y/|y|  (Chen eq. 1).
#pragma once

#include <cmath>

#include "cuda/kernels/bond.h"
#include "cuda/kernels/surface_correction.h"
#include "cuda/views.h"

namespace pd {

// omega = delta / |G xi|; the same from both ends of a bond (|G(-xi)| = |G xi|).
// kAnisotropic = false compiles the matrix out (every material of the run is isotropic);
// true reads G for the materials that have one. Set-up and per-frame code use the default.
template <bool kAnisotropic = true>
PD_HD inline real influence(Vec3 xi, real inv_r0, const Material& m) {
  if (!kAnisotropic || !m.anisotropic) return m.horizon * inv_r0;
  const real* g = m.aniso;
  const Vec3 gx{g[0] * xi.x + g[1] * xi.y + g[2] * xi.z, g[3] * xi.x + g[4] * xi.y + g[5] * xi.z,
                g[6] * xi.x + g[7] * xi.y + g[8] * xi.z};
  return m.horizon * fast_rsqrt(dot(gx, gx));
}

// One end's force state gathered by what it multiplies: t = omega (a (e - e^p) + c |xi|) with
// a = 15 mu / m and c = (3 K - 5 mu) theta / m (the dilatational term 3 K theta |xi| / m plus
// the deviatoric part of e, -5 mu theta |xi| / m), so a bond's two ends add their a and c.
struct ForceStateCoefficients {
  real a, c;
};

PD_HD inline ForceStateCoefficients force_state_coefficients(real theta, real inv_mw, const Material& m) {
  return {real(15) * m.shear_modulus * inv_mw,
          (real(3) * m.bulk_modulus - real(5) * m.shear_modulus) * theta * inv_mw};
}

PD_HD inline real force_state(real omega, real r0, real e, real theta, real inv_mw, real ep,
                              const Material& m) {
  const ForceStateCoefficients k = force_state_coefficients(theta, inv_mw, m);
  return omega * (k.a * (e - ep) + k.c * r0);
}

// The deviatoric elastic energy of particle i's state on one bond (LPS energy density
// W_i = K theta_i^2 / 2 + (15 mu / (2 m_i)) sum_j omega (e^d - e^p)^2 beta V_j, times V_i).
template <class Geometry>
PD_HD inline real lps_bond_energy(const Geometry& g, real theta, real inv_mw, real ep, real vol_i,
                                  const Material& m, real factor) {
  const real ed = g.e - theta * g.r0 * real(1.0 / 3.0) - ep;
  return real(7.5) * m.shear_modulus * inv_mw * (influence(g.xi, g.inv_r0, m) * factor) * ed * ed *
         g.weight(m) * vol_i;
}

// Chen eq. 18 as the paper's text means it: s^omega = (e - e^p) / delta against a limit that
// grows with the particle's damage phi, tau (1 + alpha phi). Eq. 18 as printed multiplies
// s^omega by (1 + alpha phi), which makes damaged material weaker and, for alpha > 0, more
// dust, where the text says alpha "increases the crack threshold as the material gets damaged"
// and "mitigates the shattering effect" (docs/design-decisions.md, measured there).
// The limit on e - e^p: tau (1 + alpha phi) delta, so that s^omega > tau (1 + alpha phi) is
// tested without a division (both ends of a bond evaluate it for both ends on the same numbers).
PD_HD inline real chen_extension_limit(real tau, real damage, const Material& m) {
  return tau * ((real(1) + m.damage_alpha * damage) * m.horizon);
}

// m_i over the initial family (all bonds intact), once at set-up; state[i].y holds 1/m_i, and 0
// for a particle without a family (a body of one particle), which then has no dilatation or force.
// A plastic particle starts without plastic extension: state[i].w marks it so (reads_plastic_history).
PD_HD inline void weighted_volume(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  real sum = 0;
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int32_t j = bond_partner(b.neighbor[b.slot(i, k)]);
    const Vec3 xi = xyz(p.rest[j]) - xyz(p.rest[i]);
    const real r0 = length(xi);
    sum += influence(xi, real(1) / r0, m) * surface_bond_at(b, b.slot(i, k)) * r0 * r0 *
           volume_fraction(r0, m) * p.volume(j);
  }
  p.state[i].y = sum > real(0) ? real(1) / sum : real(0);
  if (m.plastic) p.state[i].w = real(INFINITY);
}

// Whether a particle's own e^p (BondsView::plastic at its slots) may be other than zero: not for
// elastic materials, nor for a plastic particle that has never flowed, which `plasticity` marks
// with +infinity in state.w where a non-flowing particle has the factor 1 (plasticity.h
// yield_test). From `plasticity` to the next step's `init` state.w holds that mark or the factor;
// `init` reads it before writing the trial norm. Where it is false, `init` and `springforces` take
// the particle's e^p as 0 without reading them: the same bits (e - 0 is e), and in a scene whose
// flow stays near an impact most of the history is never read.
PD_HD inline bool reads_plastic_history(const Vec4& state, const Material& m) {
  return m.plastic && state.w != real(INFINITY);
}

// What `init` sums over particle i's intact bonds: theta_i, and for plastic materials (kPlastic)
// the norm |t^d| = (sum_j (t^d_j)^2 beta V_j)^(1/2) of the trial deviatoric force state
// t^d_j = (15 mu / m_i) omega (e_j - theta_i |xi_j| / 3 - e^p_j) that `plasticity` tests against
// the yield surface (plasticity.h), so the return mapping needs no pass of its own over the
// bonds of particles that do not yield. theta_i is only known after the pass, so the pass sums
// around theta_prev (the last step's theta_i): with d = e - e^p - theta_prev |xi| / 3 and
// D = theta_i - theta_prev, sum omega^2 beta V (d - D |xi| / 3)^2 = S_dd - (2 D / 3) S_dr +
// (D^2 / 9) S_rr. D is one step's change, so the three terms do not cancel (summing around 0
// would lose the deviatoric part of a mostly volumetric strain to float round-off). The factor
// 15 mu / m_i (~1e24 N/m^7 for steel at lambda = 1 mm, growing as delta^-5) multiplies the
// square root: the squared norm overflows float for stiff metals at fine spacing.
struct DilatationPass {
  real theta;
  real trial_norm;  // |t^d| (kPlastic, plastic materials), else 0; negative (-0 for 0) where the
                    // particle has never flowed (reads_plastic_history false), as `plasticity` reads it
};

// One pass, with (kNorm) or without the trial norm; a team's lanes sum their shares, then the team's.
template <bool kAnisotropic, int kLattice, bool kNorm, int kThreads>
PD_HD inline DilatationPass dilatation_pass(int32_t i, const ParticlesView& p, const BondsView& b,
                                            const Material& m, const Team<kThreads>& team) {
  const real theta_prev = kNorm ? p.state[i].x : real(0);
  // The lattice loop skips a particle's history where it has none (plastic_at) and so needs the
  // mark before it; the listed loop loads the history anyway. The mark that sets the trial norm's
  // sign is read again after the loop, with 1/m, rather than held over it (one H200, bench/NOTES.md:
  // plastic `init` 3% faster on the lattice, 7% on explicit families, 12% on Chen's plastic wall).
  const bool history = kNorm && kLattice != kNoLattice && reads_plastic_history(p.state[i], m);
  real sum = 0, s_dd = 0, s_dr = 0, s_rr = 0;
  const uint16_t* row = surface_row_of(b, i);
  const PartialVolumes volumes = partial_volumes_of(m);  // once per particle (bond.h)
  // The entry loop unrolled 8 times: plastic init -3% time against the compiler's 2 (bench/NOTES.md);
  // the trial norm's history fetched ahead.
  constexpr int kHistory = kNorm ? kOwnHistory : kNoHistory;
  for_each_intact_bond<kLattice, 8, kHistory>(
      i, p, b, team,
      [&](int64_t slot, int32_t, const auto& g) {
        const real omega = influence<kAnisotropic>(g.xi, g.inv_r0, m) * surface_factor_of(b, slot, g, row),
                   weight = g.weight(volumes);
        sum += omega * g.r0 * g.e * weight;
        if constexpr (kNorm) {
          const real d = g.e - plastic_at(b.plastic, slot, history, g) - theta_prev * g.r0 * real(1.0 / 3.0);
          const real ww = omega * omega * weight;
          s_dd += ww * d * d;
          s_dr += ww * d * g.r0;
          s_rr += ww * g.r0 * g.r0;
        }
      },
      history);
  sum = team.sum(sum);
  if constexpr (kNorm) {
    s_dd = team.sum(s_dd);
    s_dr = team.sum(s_dr);
    s_rr = team.sum(s_rr);
  }
  const real inv_mw = p.state[i].y;
  DilatationPass out{real(3) * sum * inv_mw, real(0)};
  if constexpr (kNorm) {
    const real shift = out.theta - theta_prev, alpha = real(15) * m.shear_modulus * inv_mw;
    const real norm2 = s_dd - real(2.0 / 3.0) * shift * s_dr + real(1.0 / 9.0) * shift * shift * s_rr;
    out.trial_norm = alpha * std::sqrt(norm2 > real(0) ? norm2 : real(0));
    if (!reads_plastic_history(p.state[i], m)) out.trial_norm = -out.trial_norm;
  }
  return out;
}

// kPlastic: the scene has plastic materials; their particles also get the trial norm, the
// elastic bodies of such a scene sum theta alone (one branch per particle, none per bond).
template <bool kAnisotropic = true, int kLattice = kLatticeListed, bool kPlastic = false, int kThreads = 1>
PD_HD inline DilatationPass dilatation(int32_t i, const ParticlesView& p, const BondsView& b,
                                       const Material& m, const Team<kThreads>& team = {}) {
  if constexpr (kPlastic)
    if (m.plastic) return dilatation_pass<kAnisotropic, kLattice, true>(i, p, b, m, team);
  return dilatation_pass<kAnisotropic, kLattice, false>(i, p, b, m, team);
}

}  // namespace pd
