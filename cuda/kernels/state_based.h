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

#include "../views.h"
#include "bond.h"

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

PD_HD inline real force_state(real omega, real r0, real e, real theta, real inv_mw, real ep,
                              const Material& m) {
  const real dil = real(3) * m.bulk_modulus * theta * r0;
  const real dev = real(15) * m.shear_modulus * (e - theta * r0 * real(1.0 / 3.0) - ep);
  return omega * inv_mw * (dil + dev);
}

// The deviatoric elastic energy of particle i's state on one bond (LPS energy density
// W_i = K theta_i^2 / 2 + (15 mu / (2 m_i)) sum_j omega (e^d - e^p)^2 beta V_j, times V_i).
template <class Geometry>
PD_HD inline real lps_bond_energy(const Geometry& g, real theta, real inv_mw, real ep, real vol_i,
                                  const Material& m) {
  const real ed = g.e - theta * g.r0 * real(1.0 / 3.0) - ep;
  return real(7.5) * m.shear_modulus * inv_mw * influence(g.xi, g.inv_r0, m) * ed * ed * g.weight(m) * vol_i;
}

// Chen eq. 18 as the paper's text means it: s^omega = (e - e^p) / delta against a limit that
// grows with the particle's damage phi, tau (1 + alpha phi). Eq. 18 as printed multiplies
// s^omega by (1 + alpha phi), which makes damaged material weaker and, for alpha > 0, more
// dust, where the text says alpha "increases the crack threshold as the material gets damaged"
// and "mitigates the shattering effect" (docs/design-decisions.md, measured there).
// Whether s^omega exceeds `limit` (1 + alpha phi), tested without a division (both ends of a
// bond evaluate it for both ends on the same numbers).
PD_HD inline bool chen_breaks(real e, real ep, real damage, real limit, const Material& m) {
  return e - ep > limit * ((real(1) + m.damage_alpha * damage) * m.horizon);
}

// m_i over the initial family (all bonds intact), once at set-up; state[i].y holds 1/m_i.
PD_HD inline void weighted_volume(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  real sum = 0;
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int32_t j = bond_partner(b.neighbor[b.slot(i, k)]);
    const Vec3 xi = xyz(p.rest[j]) - xyz(p.rest[i]);
    const real r0 = length(xi);
    sum += influence(xi, real(1) / r0, m) * r0 * r0 * volume_fraction(r0, m) * p.volume(j);
  }
  p.state[i].y = real(1) / sum;
}

// theta_i over the intact bonds.
template <bool kAnisotropic = true, bool kLattice = true>
PD_HD inline real dilatation(int32_t i, const ParticlesView& p, const BondsView& b, const Material& m) {
  real sum = 0;
  for_each_intact_bond<kLattice>(i, p, b, [&](int64_t, int32_t, const auto& g) {
    sum += influence<kAnisotropic>(g.xi, g.inv_r0, m) * g.r0 * g.e * g.weight(m);
  });
  return real(3) * sum * p.state[i].y;
}

}  // namespace pd
