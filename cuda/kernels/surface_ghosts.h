// The ghost surface correction (a material's `surface_correction = "ghosts"`; bench/NOTES.md,
// issue 29): a particle near a free surface completes its family with ghosts. Each bond its
// family misses (an offset of the interior lattice family ending outside the body) ends at a
// private ghost, displaced by the quadratic field fitted to the particle's own family:
//   u(x_i + xi) - u_i = C_i p(xi),  p(xi) = (x, y, z, x^2, y^2, z^2, xy, yz, xz) of xi / delta,
//   C_i = D_i A_i^-1,  D_i = sum_k (u_k - u_i) w_k p(xi_k)^T,  A_i = sum_k w_k p(xi_k) p(xi_k)^T,
// w_k = omega beta V_k over the particle's bonds. The ghosts own no energy: the particle's energy
// density sums its real and ghost bonds as an interior particle's does (PMB: a quarter of c s^2
// |xi| beta V_o per bond; LPS: ghost bonds in theta_i and in the deviatoric sum, m_i the
// interior's), so under any field the fit reproduces (uniform strains, and the bending that a
// linear fit misses) a surface particle stores what the interior does. The energy depends on the
// real particles through C_i, so the ghost bonds' forces g_o = dW / dy_o go back to the family:
//   f_k -= M_i p(xi_k) w_k,  f_i += M_i sum_k p(xi_k) w_k,  M_i = (sum_o g_o p(xi_o)^T) A_i^-1,
// which sums to zero and, W being invariant under rotations, exerts no torque: momentum and
// angular momentum are kept, and the forces come from an energy.
// Per step: `ghost_fit` after `init` (the fit, the ghosts' stretches, theta_i completed, M_i and
// M_i s_i), `ghost_push` (each partner's share M_i p(xi_k) w_k written to the bond's row of the push
// table), `ghost_forces` after `springforces` (each particle near a surface adds its own M_i s_i
// and takes off, through its bonds' mirror rows, the shares its ghosted partners pushed to it: 16
// bytes a bond, where reading each partner's M took 112 and the basis again), `ghost_drops` (the
// particles that lost a bond in this step drop their ghosts). On the GPU the fit
// and the push run a team of lanes per ghosted particle (cuda/team.h): the lanes split
// the family's bonds and the ghosts and add their partial sums in the team's fixed tree; Team<1>
// (the CPU, or PERIFRAC_BOND_THREADS=1) is one thread per particle. A particle's ghosts are dropped for good
// once any of its bonds is broken (its fit would reach across the crack): it is then an uncorrected particle
// at a crack, and the energy its ghost bonds held is booked as released. Pre-cracked particles never have
// ghosts. Set-up: cuda/engine/surface_ghosts.h.
#pragma once

#include "cuda/kernels/bond.h"
#include "cuda/kernels/family.h"
#include "cuda/kernels/springforces.h"
#include "cuda/kernels/state_based.h"
#include "cuda/team.h"

namespace pd {

constexpr int kGhostBasis = 9;
// Floats of scratch per ghosted particle: M (3 x 9), M s (3), pad; 128 bytes, so that a row's
// 16-byte loads stay aligned.
constexpr int kGhostPull = 32;
// GhostView::live of a ghosted particle one of whose bonds broke in this step's force pass, until
// ghost_drops drops its ghosts.
constexpr uint8_t kGhostsGoing = 2;

// The ghosted particles' tables (built at set-up, cuda/engine/surface_ghosts.h).
struct GhostView {
  int32_t n = 0;                        // ghosted particles
  ArrayView<const int32_t> particle;    // [n] the particle
  ArrayView<const int32_t> of;          // [particles] its row here, or -1
  ArrayView<const real> inverse;        // [n x 81] A^-1, row major
  ArrayView<const real> moment;         // [n x 9] A^-1 sum_k w_k p(xi_k), over the family
  ArrayView<const real> inv_mw;         // [n] LPS: 1 / m over the family and the ghosts (the interior's)
  ArrayView<const int32_t> first;       // [n + 1] the particle's ghosts in `offset`
  ArrayView<const Vec4> offset;         // xyz: a ghost bond's reference vector; w: its weight beta V_o
  ArrayView<const int32_t> receivers;   // particles that are ghosted or bond to one
  ArrayView<const int32_t> push_first;  // [n + 1] the particle's bonds' rows in `push`, in family order
  ArrayView<const int32_t> mirror;      // [bond slots] the row of `push` where the slot's partner, if
                                        // ghosted, puts this end's share (ghost_mirror), else -1
  ArrayView<real> pull;                 // [n x kGhostPull] this step's M and M s
  ArrayView<Vec4> push;                 // xyz: this step's share of the ghosted particle's bond k
  ArrayView<uint8_t> live;              // [n] 1 while every bond of the particle holds (kGhostsGoing
                                        // between ghost_forces and ghost_drops once one broke)
};

// p(xi) with xi in units of delta.
PD_HD inline void ghost_basis(Vec3 xi, real inv_delta, real* q) {
  const real x = xi.x * inv_delta, y = xi.y * inv_delta, z = xi.z * inv_delta;
  q[0] = x;
  q[1] = y;
  q[2] = z;
  q[3] = x * x;
  q[4] = y * y;
  q[5] = z * z;
  q[6] = x * y;
  q[7] = y * z;
  q[8] = x * z;
}

// The fit's weight of a bond: omega beta V_k (omega = delta / |xi|; ghosts need an isotropic
// influence, the loader refuses anisotropy with them).
PD_HD inline real ghost_fit_weight(real r0, real volume, const Material& m) {
  return m.horizon / r0 * volume_fraction(r0, m) * volume;
}

// out = x A_g^-1 for x and out 3 x 9 (row major), A_g^-1 the ghosted particle g's.
PD_HD inline void times_inverse(const real* x, int32_t g, const GhostView& gv, real* out) {
  const real* inv = gv.inverse.data() + int64_t(g) * kGhostBasis * kGhostBasis;
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < kGhostBasis; ++a) {
      real s = 0;
      for (int q = 0; q < kGhostBasis; ++q) s += x[c * kGhostBasis + q] * inv[q * kGhostBasis + a];
      out[c * kGhostBasis + a] = s;
    }
}

// The same over a team, every lane ending with all of out: lane l sums the columns l, l +
// kSize, ... of the three rows (each entry's sum in times_inverse's order, so the same bits), and
// the lanes pass them round, where each lane summing all 27 took 243 multiply-adds.
template <class TeamT>
PD_HD inline void times_inverse(const real* x, int32_t g, const GhostView& gv, real* out, const TeamT& team) {
  if constexpr (TeamT::kSize == 1) {
    times_inverse(x, g, gv, out);
  } else {
    constexpr int kRounds = (kGhostBasis + TeamT::kSize - 1) / TeamT::kSize;
    const real* inv = gv.inverse.data() + int64_t(g) * kGhostBasis * kGhostBasis;
    real mine[kRounds][3];
    for (int r = 0; r < kRounds; ++r) {
      const int col = r * TeamT::kSize + team.lane();
      const int a = col < kGhostBasis ? col : kGhostBasis - 1;  // (lanes past the last repeat it)
      for (int c = 0; c < 3; ++c) {
        real s = 0;
        for (int q = 0; q < kGhostBasis; ++q) s += x[c * kGhostBasis + q] * inv[q * kGhostBasis + a];
        mine[r][c] = s;
      }
    }
    for (int a = 0; a < kGhostBasis; ++a)
      for (int c = 0; c < 3; ++c)
        out[c * kGhostBasis + a] = team.from(a % TeamT::kSize, mine[a / TeamT::kSize][c]);
  }
}

// One ghosted particle's fitted field: C = D A^-1 (3 x 9), row major.
struct GhostFit {
  real c[3 * kGhostBasis];
};

// Every lane of `team` ends with the same fit.
template <class TeamT = Team<1>>
PD_HD inline GhostFit fit_ghost_field(int32_t g, int32_t i, const ParticlesView& p, const BondsView& b,
                                      const GhostView& gv, const Material& m, const TeamT& team = {}) {
  real d[3 * kGhostBasis] = {};
  const Vec3 rest_i = xyz(p.rest[i]), disp_i = xyz(p.disp[i]);
  const real inv_delta = real(1) / m.horizon;
  for (int32_t k = team.lane(); k < b.count[i]; k += TeamT::kSize) {
    const int32_t j = bond_partner(b.neighbor[b.slot(i, k)]);
    const Vec4 rest_j = p.rest[j];
    const Vec3 xi = xyz(rest_j) - rest_i;
    const real w = ghost_fit_weight(length(xi), rest_j.w, m);
    const Vec3 du = (xyz(p.disp[j]) - disp_i) * w;
    real q[kGhostBasis];
    ghost_basis(xi, inv_delta, q);
    for (int a = 0; a < kGhostBasis; ++a) {
      d[a] += du.x * q[a];
      d[kGhostBasis + a] += du.y * q[a];
      d[2 * kGhostBasis + a] += du.z * q[a];
    }
  }
  if constexpr (TeamT::kSize > 1)
    for (int a = 0; a < 3 * kGhostBasis; ++a) d[a] = team.sum(d[a]);
  GhostFit f;
  times_inverse(d, g, gv, f.c, team);
  return f;
}

// One ghost bond at the fitted field: its reference and current vectors, lengths and extension.
struct GhostBond {
  Vec3 y;
  real r0, inv_r, e, weight;
  real q[kGhostBasis];
};

PD_HD inline GhostBond ghost_bond(const GhostFit& f, Vec4 offset, real inv_delta) {
  GhostBond o;
  const Vec3 xi = xyz(offset);
  ghost_basis(xi, inv_delta, o.q);
  Vec3 eta{0, 0, 0};
  for (int a = 0; a < kGhostBasis; ++a) {
    eta.x += f.c[a] * o.q[a];
    eta.y += f.c[kGhostBasis + a] * o.q[a];
    eta.z += f.c[2 * kGhostBasis + a] * o.q[a];
  }
  o.y = xi + eta;
  const BondLengths l = bond_lengths(xi, o.y);
  o.r0 = l.r0;
  o.inv_r = l.inv_r;
  o.e = bond_elongation(xi, eta, l.sum);
  o.weight = offset.w;
  return o;
}

// theta_i with the ghost bonds (LPS): init's sum over the real bonds, taken with 1/m of the
// interior, plus the ghosts' share.
template <class TeamT = Team<1>>
PD_HD inline real ghost_dilatation(const GhostFit& f, int32_t g, real theta_real, real inv_mw,
                                   const GhostView& gv, const Material& m, const TeamT& team = {}) {
  const real inv_delta = real(1) / m.horizon;
  real sum = 0;
  for (int32_t o = gv.first[g] + team.lane(); o < gv.first[g + 1]; o += TeamT::kSize) {
    const GhostBond gb = ghost_bond(f, gv.offset[o], inv_delta);
    sum += m.horizon * gb.e * gb.weight;  // omega |xi| e beta V_o, omega |xi| = delta
  }
  return theta_real + real(3) * team.sum(sum) * inv_mw;
}

// The energy the particle's ghost bonds hold (V_i times their share of its energy density; LPS:
// the deviatoric part, theta's K theta^2 / 2 being counted with the particle's own).
PD_HD inline double ghost_bond_energy(const GhostFit& f, int32_t g, int32_t i, const ParticlesView& p,
                                      const GhostView& gv, const Material& m, real theta, real inv_mw) {
  const real inv_delta = real(1) / m.horizon, vol_i = p.volume(i);
  double sum = 0;
  for (int32_t o = gv.first[g]; o < gv.first[g + 1]; ++o) {
    const GhostBond gb = ghost_bond(f, gv.offset[o], inv_delta);
    if (m.model == kStateBased) {
      const real ed = gb.e - theta * gb.r0 * real(1.0 / 3.0);
      sum += double(real(7.5) * m.shear_modulus * inv_mw * (m.horizon / gb.r0) * ed * ed * gb.weight * vol_i);
    } else {
      sum += double(pmb_bond_energy(gb.e / gb.r0, gb.r0, vol_i, gb.weight, m));
    }
  }
  return sum;
}

// Kernel `ghost_fit`, after `init`: the fit, theta_i completed (LPS), and M_i and M_i s_i for
// `ghost_forces` (zeros for a particle whose ghosts were dropped).
template <class TeamT = Team<1>>
PD_HD inline void ghost_fit(int32_t g, ParticlesView p, BondsView b, GhostView gv, const MaterialTable& mt,
                            const TeamT& team = {}) {
  real* pull = gv.pull.data() + int64_t(g) * kGhostPull;
  if (!gv.live[g]) {
    for (int a = team.lane(); a < kGhostPull; a += TeamT::kSize) pull[a] = 0;
    return;
  }
  const int32_t i = gv.particle[g];
  const Material& m = mt.m[p.material[i]];
  const bool state = m.model == kStateBased;
  const GhostFit f = fit_ghost_field(g, i, p, b, gv, m, team);
  const real inv_m_full = state ? gv.inv_mw[g] : real(0);
  const real inv_delta = real(1) / m.horizon, vol_i = p.volume(i);
  ForceStateCoefficients k{0, 0};
  if (state) {
    Vec4 s = p.state[i];
    s.x = ghost_dilatation(f, g, s.x, inv_m_full, gv, m, team);
    if (team.leader()) p.state[i] = s;
    k = force_state_coefficients(s.x, inv_m_full, m);
  }
  // Q = sum_o g_o p(xi_o)^T
  real q_sum[3 * kGhostBasis] = {};
  for (int32_t o = gv.first[g] + team.lane(); o < gv.first[g + 1]; o += TeamT::kSize) {
    const GhostBond gb = ghost_bond(f, gv.offset[o], inv_delta);
    const real t =
        state ? (m.horizon / gb.r0) * (k.a * gb.e + k.c * gb.r0) : real(0.5) * m.micromodulus * gb.e / gb.r0;
    const Vec3 go = (t * gb.weight * vol_i * gb.inv_r) * gb.y;
    for (int a = 0; a < kGhostBasis; ++a) {
      q_sum[a] += go.x * gb.q[a];
      q_sum[kGhostBasis + a] += go.y * gb.q[a];
      q_sum[2 * kGhostBasis + a] += go.z * gb.q[a];
    }
  }
  if constexpr (TeamT::kSize > 1)
    for (int a = 0; a < 3 * kGhostBasis; ++a) q_sum[a] = team.sum(q_sum[a]);
  // M = Q A^-1, and M s with s = sum_k w_k p(xi_k) (the particle's own force)
  real mq[3 * kGhostBasis];
  times_inverse(q_sum, g, gv, mq, team);
  if (!team.leader()) return;
  for (int a = 0; a < 3 * kGhostBasis; ++a) pull[a] = mq[a];
  // M s = Q (A^-1 s), A^-1 s fixed at set-up (s = sum_k w_k p(xi_k) over the intact family)
  const real* t = gv.moment.data() + int64_t(g) * kGhostBasis;
  Vec3 own{0, 0, 0};
  for (int a = 0; a < kGhostBasis; ++a) {
    own.x += q_sum[a] * t[a];
    own.y += q_sum[kGhostBasis + a] * t[a];
    own.z += q_sum[2 * kGhostBasis + a] * t[a];
  }
  pull[27] = own.x;
  pull[28] = own.y;
  pull[29] = own.z;
}

// Kernel `ghost_push`, after `ghost_fit`: each partner k's share w_k M p(xi_k) of ghosted particle
// g's ghost bonds' forces (xi_k from g's particle to k), which ghost_forces takes off k's force; 0
// once g's ghosts are dropped (its M is 0).
template <class TeamT = Team<1>>
PD_HD inline void ghost_push(int32_t g, ParticlesView p, BondsView b, GhostView gv, const MaterialTable& mt,
                             const TeamT& team = {}) {
  const int32_t i = gv.particle[g];
  const int32_t first = gv.push_first[g], count = gv.push_first[g + 1] - first;
  // M in seven 16-byte loads (a float each would take 27 load instructions).
  real mq[28];
  const Vec4* rows = reinterpret_cast<const Vec4*>(gv.pull.data() + int64_t(g) * kGhostPull);
  for (int v = 0; v < 7; ++v) {
    const Vec4 r4 = rows[v];
    mq[4 * v] = r4.x;
    mq[4 * v + 1] = r4.y;
    mq[4 * v + 2] = r4.z;
    mq[4 * v + 3] = r4.w;
  }
  const Material& m = mt.m[p.material[i]];
  const real inv_delta = real(1) / m.horizon;
  const Vec3 rest_i = xyz(p.rest[i]);
  for (int32_t k = team.lane(); k < count; k += TeamT::kSize) {
    const Vec4 rest_k = p.rest[bond_partner(b.neighbor[b.slot(i, k)])];
    const Vec3 xi = xyz(rest_k) - rest_i;
    const real w = ghost_fit_weight(length(xi), rest_k.w, m);
    real q[kGhostBasis];
    ghost_basis(xi, inv_delta, q);
    Vec3 pk{0, 0, 0};
    for (int a = 0; a < kGhostBasis; ++a) {
      pk.x += mq[a] * q[a];
      pk.y += mq[kGhostBasis + a] * q[a];
      pk.z += mq[2 * kGhostBasis + a] * q[a];
    }
    gv.push[first + k] = with_w(w * pk, 0);
  }
}

// A ghosted particle one of whose bonds broke in this step's force pass loses its ghosts (after
// this step's forces, which its fit took with the bond), as if its ghost bonds broke with it:
// their energy leaves the books (LPS: their deviatoric energy and the change of K theta^2 / 2
// as theta loses their share; m stays the interior's, as m stays the initial family's when real
// bonds break). Between steps, then, a particle's ghosts hold exactly while all its bonds do,
// which is what a restore rebuilds (ghost_liveness).
PD_HD inline void drop_ghosts(int32_t g, int32_t i, ParticlesView p, BondsView b, GhostView gv,
                              const MaterialTable& mt) {
  const Material& m = mt.m[p.material[i]];
  const GhostFit f = fit_ghost_field(g, i, p, b, gv, m);
  if (m.model == kStateBased) {
    Vec4 s = p.state[i];
    const real inv_mw = gv.inv_mw[g];
    const real theta_real = s.x - ghost_dilatation(f, g, 0, inv_mw, gv, m);
    p.ledger[i].released += ghost_bond_energy(f, g, i, p, gv, m, s.x, inv_mw) +
                            0.5 * double(m.bulk_modulus) * double(p.volume(i)) *
                                (double(s.x) * double(s.x) - double(theta_real) * double(theta_real));
    s.x = theta_real;
    p.state[i] = s;
  } else {
    p.ledger[i].released += ghost_bond_energy(f, g, i, p, gv, m, 0, 0);
  }
  gv.live[g] = 0;
}

// Kernel `ghost_forces`, after `springforces`: receiver r's share of the ghost bonds' forces,
// its own ghosts' and those its ghosted partners pushed to it (every bond, including one broken
// in this step's force pass: the partner's fit still took it), added to its force.
template <class TeamT = Team<1>>
PD_HD inline void ghost_forces(int32_t r, ParticlesView p, BondsView b, GhostView gv,
                               const TeamT& team = {}) {
  const int32_t i = gv.receivers[r];
  Vec3 f{0, 0, 0};
  const int32_t own = gv.of[i];
  if (own >= 0 && team.leader()) {
    const real* pull = gv.pull.data() + int64_t(own) * kGhostPull;
    f = {pull[27], pull[28], pull[29]};
  }
  bool intact = true;
  const int64_t first_slot = b.slot(i, 0);
  for (int32_t k = team.lane(); k < b.count[i]; k += TeamT::kSize) {
    const int64_t slot = first_slot + int64_t(k) * kSliceWidth;
    if (own >= 0) intact = intact && bond_intact(b.neighbor[slot]);
    const int32_t row = gv.mirror[slot];
    if (row >= 0) f -= xyz(gv.push[row]);
  }
  if constexpr (TeamT::kSize > 1) {
    f = team.sum(f);
    intact = team.sum(int32_t(!intact)) == 0;
  }
  if (!team.leader()) return;
  p.force[i] += f;
  if (own >= 0 && !intact && gv.live[own]) gv.live[own] = kGhostsGoing;
}

// Kernel `ghost_drops`, after `ghost_forces`: the particles that lost a bond in this step drop their
// ghosts (drop_ghosts). Its own kernel: drop_ghosts' fit and energies inlined into ghost_forces held
// that gather at 72-128 registers for a path it rarely takes.
PD_HD inline void ghost_drops(int32_t g, ParticlesView p, BondsView b, GhostView gv,
                              const MaterialTable& mt) {
  if (gv.live[g] == kGhostsGoing) drop_ghosts(g, gv.particle[g], p, b, gv, mt);
}

// Set-up, after the push table's rows (GhostView::push_first): each slot of particle i gets the
// row where its partner, if ghosted, pushes i's share (families are symmetric and in ascending
// partner order: family.h position_in_family), else -1.
PD_HD inline void ghost_mirror(int32_t i, const BondsView& b, const GhostView& gv, int32_t* mirror) {
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int64_t slot = b.slot(i, k);
    const int32_t j = bond_partner(b.neighbor[slot]), g = gv.of[j];
    const int32_t q = g < 0 ? -1 : position_in_family(b, j, i);
    mirror[slot] = q < 0 ? -1 : gv.push_first[g] + q;
  }
}

// The ghost bonds' energy of ghosted particle g (0 once its ghosts are dropped).
PD_HD inline double ghost_energy(int32_t g, const ParticlesView& p, const BondsView& b, const GhostView& gv,
                                 const MaterialTable& mt) {
  if (!gv.live[g]) return 0;
  const int32_t i = gv.particle[g];
  const Material& m = mt.m[p.material[i]];
  const bool state = m.model == kStateBased;
  const GhostFit f = fit_ghost_field(g, i, p, b, gv, m);
  return ghost_bond_energy(f, g, i, p, gv, m, state ? p.state[i].x : real(0), state ? gv.inv_mw[g] : real(0));
}

// State-based set-up, after the weighted volumes: a ghosted particle's 1/m is the interior's
// (over its family and its ghosts), which init's theta over the real bonds then takes, and
// which it keeps when its ghosts go.
PD_HD inline void ghost_weighted_volume(int32_t g, ParticlesView p, const GhostView& gv) {
  p.state[gv.particle[g]].y = gv.inv_mw[g];
}

// Whether particle g's ghosts hold: every bond of the particle intact (set-up and after a
// restore; drop_ghosts keeps it from then on).
PD_HD inline void ghost_liveness(int32_t g, const BondsView& b, GhostView gv) {
  const int32_t i = gv.particle[g];
  uint8_t live = 1;
  for (int32_t k = 0; k < b.count[i]; ++k) live = live && bond_intact(b.neighbor[b.slot(i, k)]);
  gv.live[g] = live;
}

}  // namespace pd
