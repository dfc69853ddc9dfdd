// Kernel 4, `springforces` (bond-based PMB, Silling & Askari 2005; Levine sec. 3). For each
// bond of particle i: stretch s = (|y| - |xi|)/|xi| with y = xi + (u_j - u_i); remove the
// bond when s > w max(tau'_i, tau'_j) (w the bond's strength, 1 unless the scene weakens
// bonds; both ends decide identically, so momentum is kept);
// record the minimum stretch for eq. 5; accumulate f_i = sum_j c g_ij s V_i V_j beta_ij y/|y|
// (g_ij the surface correction's factor, 1 without it; beta_ij V_j g_ij: surface_bond_weight).
#pragma once

#include <cmath>

#include "cuda/kernels/bond.h"
#include "cuda/kernels/bond_screen.h"
#include "cuda/kernels/surface_correction.h"

namespace pd {

// One end's share of a PMB bond's elastic energy: the micropotential c s^2 |xi| / 2 per unit
// volume squared, halved between the two ends: c s^2 |xi| beta V_i V_j / 4 (weight_j = beta V_j).
PD_HD inline real pmb_bond_energy(real s, real r0, real vol_i, real weight_j, const Material& m) {
  return real(0.25) * m.micromodulus * s * s * r0 * vol_i * weight_j;
}

// A bond's weight beta V_j times the surface correction's factor g on its micromodulus
// (surface_correction.h), in units of kWeightUnit<kSurface>: a lattice bond's beta V_j from its
// stencil entry and g from its particle's row of factors per stencil entry (`row`,
// surface_row_of), a listed bond's V_j times its slot's g beta, loaded ahead (SlotAhead;
// folds_partial_volume); beta V_j alone without the correction (kSurface false), at no cost.
// With the correction the stored factor's step 2^-12 is left out of every bond and the force
// pass applies it to its sum after the loop: a power of two, so the same bits, and one
// instruction a bond fewer (bench/NOTES.md).
template <bool kSurface>
constexpr real kWeightUnit = kSurface ? real(kSurfaceBondStep) : real(1);

// Without the correction a listed bond takes the partial-volume rule only where `partial` (the
// material's flag, read once before the loop, or NoPartialVolumes: with_partial_rule) says its
// material has partial volumes: PMB's default has none, and the rule's load, test and branch at
// every bond cost the explicit lattice's force pass (bench/NOTES.md).
template <bool kSurface, class Geometry, class Partial>
PD_HD inline real surface_bond_weight(const Geometry& g, const Material& m, Partial partial,
                                      const uint16_t* row) {
  if constexpr (!kSurface && std::is_same_v<Partial, bool>)
    return partial ? g.weight(m) : g.volume_j;
  else if constexpr (!kSurface)
    return g.volume_j;
  else if constexpr (std::is_same_v<Geometry, LatticeBondGeometry>)
    return g.weight(m) * real(row[g.entry]);
  else
    return g.volume_j * real(g.ahead.surface);
}

// The same weight where a bond's factor is read at its slot (the energy, once per frame): 1
// without factors, and a listed bond's slot holding g beta.
template <class Geometry>
PD_HD inline real pmb_bond_weight_at(const Geometry& g, const Material& m, const BondsView& b, int64_t slot) {
  if (!b.surface_bond) return g.weight(m);
  if constexpr (std::is_same_v<Geometry, LatticeBondGeometry>)
    return g.weight(m) * surface_bond_value(b.surface_bond[slot]);
  else
    return g.volume_j * surface_bond_value(b.surface_bond[slot]);
}

// The entry loop unrolled 8 times where bonds may be weakened, as the compiler picks (2) else
// (bench/NOTES.md: each the faster of the two for its kernel).
template <bool kWeak>
constexpr int kSpringUnroll = kWeak ? 8 : 2;

// How a listed family's loop loads ahead (bond.h ListedWalk): from the family's base without
// weakened bonds or factors, clamped otherwise (as measured).
template <bool kWeak, bool kSurface>
constexpr int kSpringWalk = kWeak || kSurface ? kWalkClamped : kWalkFromBase;

struct NoPartialVolumes {};

// Calls body(partial) with the particle's partial-volume flag for surface_bond_weight. Where the
// pass has no factors and reads every family from its list, a material without partial volumes
// (PMB's default) gets NoPartialVolumes: the loop compiled a second time with no test of the flag
// at its bonds, whose load, test, branch and convergence barrier were five of the explicit
// lattice's ~65 instructions a bond (one H200, bench/NOTES.md: that pass +2.6%). Elsewhere the
// flag (lattice bonds carry their weight; factors hold the partial volume).
template <bool kSurface, int kLattice, class Body>
PD_HD inline void with_partial_rule(const Material& m, Body&& body) {
  if constexpr (!kSurface && kLattice == kNoLattice)
    if (!m.partial_volumes) return body(NoPartialVolumes{});
  body(m.partial_volumes != 0);
}

// The breaking pass: the forces, and the bonds that break now removed. Raises `broke` when one does.
// A team (team.h) sums its lanes' shares; its leader writes.
template <bool kWeak, int kLattice, bool kSurface, int kThreads, class Partial>
PD_HD inline void spring_forces_with(int32_t i, ParticlesView p, BondsView b, const Material& m,
                                     int32_t* broke, const Team<kThreads>& team, Partial partial) {
  const real vol_i = p.volume(i), tau_i = p.strain_limit(i);
  Vec3 f{0, 0, 0};  // sum over the intact bonds of s beta V_j g y/|y| (c V_i applied once at the end)
  real smin = real(INFINITY);
  ReleasedEnergy<kThreads> released;
  const uint16_t* row = surface_row_of<kSurface>(b, i);
  const int32_t intact = for_each_intact_bond<kLattice, kSpringUnroll<kWeak>, kNoHistory, kSurface,
                                              kSpringWalk<kWeak, kSurface>>(
      i, p, b, team, [&](int64_t slot, int32_t, const auto& g) {
        const real s = g.e * g.inv_r0;
        const real weight = surface_bond_weight<kSurface>(g, m, partial, row);
        if (s > max_of(tau_i, g.tau_j) * bond_strength<kWeak>(b, slot, g)) {
          released.add(p, i, double(pmb_bond_energy(s, g.r0, vol_i, weight * kWeightUnit<kSurface>, m)));
          if (kRaiseInBranch<kWeak>) raise_flag(broke);
          return false;  // broken: for_each_intact_bond records it
        }
        smin = min_of(s, smin);
        f += (s * weight * g.inv_r) * g.y;
        return true;
      });
  released.settle(p, i, team);
  write_bond_forces(i, p, (m.micromodulus * vol_i) * (team.sum(f) * kWeightUnit<kSurface>), team.min(smin),
                    intact, kRaiseInBranch<kWeak> ? nullptr : broke, team);
}
// Particle i's breaking pass, its material's partial-volume rule chosen once (with_partial_rule).
template <bool kWeak, int kLattice = kLatticeListed, bool kSurface = false, int kThreads = 1>
PD_HD inline void spring_forces(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                int32_t* broke, const Team<kThreads>& team = {}) {
  const Material& m = mt.m[p.material[i]];
  with_partial_rule<kSurface, kLattice>(m, [&](auto partial) {
    spring_forces_with<kWeak, kLattice, kSurface>(i, p, b, m, broke, team, partial);
  });
}

// The screened pass (bond_screen.h): the same sums with no breaking path, and after the loop
// the test that every break needs, s > w tau_i at the particle's own end (tau_i <= max(tau_i,
// tau_j)); where it holds, the breaking pass runs for the particle from the start and its results
// are kept. The sums are the breaking pass's expressions in its order, so where no bond breaks
// both passes give the same bits.
template <bool kWeak, int kLattice, bool kSurface, int kThreads, class Partial>
PD_HD inline void screened_spring_forces_with(int32_t i, ParticlesView p, BondsView b, const Material& m,
                                              int32_t* broke, const Team<kThreads>& team, Partial partial) {
  // The volume and the strain limit (which only weakened bonds use in the loop): read after the
  // loop on explicit families of one thread a particle, held over it elsewhere, as measured (one
  // H200, bench/NOTES.md: read late, the explicit lattice's pass +1.2%, the lattice's -2.3%, teams'
  // -0.4%).
  constexpr bool kEarly = kWeak || kLattice != kNoLattice || kThreads > 1;
  const real vol_early = kEarly ? p.volume(i) : real(0), tau_early = kEarly ? p.strain_limit(i) : real(0);
  Vec3 f{0, 0, 0};
  real smin = real(INFINITY);
  real nearest = -real(INFINITY);  // the largest s - w tau_i (s alone without weakened bonds)
  const uint16_t* row = surface_row_of<kSurface>(b, i);
  const int32_t intact = for_each_intact_bond<kLattice, kSpringUnroll<kWeak>, kNoHistory, kSurface,
                                              kSpringWalk<kWeak, kSurface>>(
      i, p, b, team, [&](int64_t slot, int32_t, const auto& g) {
        const real s = g.e * g.inv_r0;
        nearest = max_of(nearest, kWeak ? s - bond_strength<kWeak>(b, slot, g) * tau_early : s);
        smin = min_of(s, smin);
        f += (s * surface_bond_weight<kSurface>(g, m, partial, row) * g.inv_r) * g.y;
      });
  if (may_break<kWeak>(team.max(nearest), kEarly ? tau_early : p.strain_limit(i)))
    return spring_forces_with<kWeak, kLattice, kSurface>(i, p, b, m, broke, team, partial);
  write_bond_forces(
      i, p, (m.micromodulus * (kEarly ? vol_early : p.volume(i))) * (team.sum(f) * kWeightUnit<kSurface>),
      team.min(smin), intact, nullptr, team);
}
// Particle i's screened pass, its material's partial-volume rule chosen once (with_partial_rule).
template <bool kWeak, int kLattice = kLatticeListed, bool kSurface = false, int kThreads = 1>
PD_HD inline void screened_spring_forces(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                         int32_t* broke, const Team<kThreads>& team = {}) {
  const Material& m = mt.m[p.material[i]];
  with_partial_rule<kSurface, kLattice>(m, [&](auto partial) {
    screened_spring_forces_with<kWeak, kLattice, kSurface>(i, p, b, m, broke, team, partial);
  });
}

}  // namespace pd
