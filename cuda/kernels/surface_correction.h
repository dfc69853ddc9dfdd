// The surface correction, computed once at set-up: the energy method with a factor per direction
// (Madenci & Oterkus 2014, sec. 4.2; reviewed by Le & Bobaru 2018, Comput. Mech. 61:499).
// Bond-based: under a uniaxial strain eps along axis k a PMB particle's energy density is
// c eps^2 sum_j n_k^4 |xi| beta V_j / 4 (n = xi / |xi|), a sum over its family, which a free surface
// cuts short. Particle i's factor along k is g_k = A / sum_j n_k^4 |xi| beta V_j, with A the same
// sum over a family inside the lattice (Material::axial_sum), so that each of the three uniaxial
// strains stores the interior's energy. A bond along n takes
//   G = (sum_k (n_k / gbar_k)^2)^(-1/2),  gbar_k = (g_k,i + g_k,j) / 2
// (the ellipse through the three axes' mean factors) on its micromodulus, the same from both
// ends: it stays a pair potential that keeps momentum and energy.
// State-based: the solid's dilatation theta = (3 / m) sum_j omega |xi| e beta V_j is exact under a
// uniform strain only where the family's second moment sum_j omega |xi|^2 beta V_j n n is
// isotropic; a cut family (a sphere minus a cap, an edge) has more along the surface than across
// it, and the bar comes out too stiff. The factors are those of the second moment's diagonal,
// sum_j omega n_k^2 |xi|^2 beta V_j against the interior's m / 3, and G multiplies the influence
// function omega of the bond in every sum (m, theta, the force and energy states, the yield norm):
// a state-based solid with another influence function, whose forces still come from an energy.
// Inside the body every factor is 1. G is stored per bond slot in 16 bits (below); the force
// and dilatation kernels read a lattice bond's from a table of rows shared by the particles
// placed alike in their body (cuda/engine/lattice_families.h surface_rows), which stays in cache
// and spares the loop the slot's index. Pre-cracks are not surfaces: the factors come from the families
// before the cuts (cuda/engine/engine_impl.h).
#pragma once

#include "cuda/kernels/bond.h"

namespace pd {

// A bound on a factor: a corner's family keeps about an eighth of the interior's sums; a
// particle with fewer bonds (a strand, a lone particle) is not made stiffer than that.
constexpr double kMaxSurfaceFactor = 8.0;

// Rounds of the factors' fixed point at set-up. One round is the energy method as published; the
// bonds from particles inside the body to the surface layer then take part of their partners'
// factors, which stiffens the layer under the surface, and further rounds take that back, at the
// cost of the lateral contraction (the factors across the surface grow). Measured on the tension
// bar 8 particles across (CPU, float, delta = 3 lambda, partial volumes), elongation error / nu:
//   PMB (nu 1/4; the interior lattice's own E is +1.4% along its axes): 1 round 6.8% / 0.246,
//   2 rounds 4.0% / 0.235, 3 rounds 2.5% / 0.230, 5 rounds 1.6% / 0.225 (none: 18% / 0.267);
//   state-based (nu 0.3): 1 round 13% / 0.304, 2 rounds 9.1% / 0.291, 3 rounds 6.5% / 0.284,
//   5 rounds 4.6% / 0.277 (none: 18% / 0.323).
// PMB takes three (the elongation within 3%, nu within 10%), state-based two (nu within 0.01).
constexpr int kSurfaceRoundsBondBased = 3;
constexpr int kSurfaceRoundsStateBased = 2;
constexpr int kSurfaceCorrectionRounds = 3;  // the most of the two

// Bond factors are stored in 16 bits, in steps of 2^-12 (surface_bond_at): 0.024% of an interior
// bond's stiffness, far below what the correction itself leaves (percents, above), and up to 16,
// past kMaxSurfaceFactor. Half the bytes a float takes: the bond-based kernels are issue-bound
// at about 1 B per bond otherwise, and every byte per bond costs them (bench/REPORT.md).
constexpr double kSurfaceBondStep = 1.0 / 4096;
constexpr uint16_t kSurfaceBondOne = 4096;

// A stored bond factor's value (exact in float).
PD_HD inline real surface_bond_value(uint32_t stored) {
  return real(stored) * real(kSurfaceBondStep);
}

// A bond's reference vector as the set-up takes it: rest_j - rest_i on a grid of 1/1024 of the
// spacing, so that on a box grid, whose bond vectors are whole spacings but for the rounding of
// the particles' positions (about 1e-5 of a spacing), particles placed alike relative to the
// body's faces get bit-identical factors (their bonds' factors are then stored once per such
// class, surface_rows in cuda/engine/lattice_families.h). Elsewhere it moves a bond by at most
// 1/2048 of the spacing.
PD_HD inline Vec3 set_up_bond_vector(Vec3 rest_i, Vec3 rest_j, const Material& m) {
  const Vec3 xi = rest_j - rest_i;
  if (!(m.spacing > 0)) return xi;
  const double q = double(m.spacing) / 1024;
  auto snap = [q](real x) {
    const double n = std::floor(std::fabs(double(x)) / q + 0.5);
    return real(x < 0 ? -n * q : n * q);
  };
  return {snap(xi.x), snap(xi.y), snap(xi.z)};
}

// Set-up, round `round`: the particle's three sums with its bonds' current factors (surface_bond,
// 1 at the start), and each of its factors times the interior's sum over its own (particles whose
// material has had its rounds keep theirs).
PD_HD inline void update_surface_factor(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                        int round) {
  const Material& m = mt.m[p.material[i]];
  if (!m.surface_correction) {
    p.surface_factor[i] = {1, 1, 1};
    return;
  }
  const bool state = m.model == kStateBased;
  if (round >= (state ? kSurfaceRoundsStateBased : kSurfaceRoundsBondBased)) return;
  const Vec3 x_i = xyz(p.rest[i]);
  double sum[3] = {0, 0, 0};
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int64_t slot = b.slot(i, k);
    const int32_t j = bond_partner(b.neighbor[slot]);
    const Vec3 xi = set_up_bond_vector(x_i, xyz(p.rest[j]), m);
    const double r0 = double(length(xi));
    const double w = double(surface_bond_value(b.surface_bond[slot])) * r0 *
                     double(volume_fraction(real(r0), m)) * double(p.volume(j));
    const double n[3] = {double(xi.x) / r0, double(xi.y) / r0, double(xi.z) / r0};
    for (int a = 0; a < 3; ++a) sum[a] += state ? w * n[a] * n[a] : w * n[a] * n[a] * n[a] * n[a];
  }
  const Vec3 old = p.surface_factor[i];
  const double g0[3] = {double(old.x), double(old.y), double(old.z)};
  double g[3];
  for (int a = 0; a < 3; ++a) {
    g[a] = sum[a] > 0 ? g0[a] * double(m.axial_sum) / sum[a] : kMaxSurfaceFactor;
    g[a] = g[a] < kMaxSurfaceFactor ? g[a] : kMaxSurfaceFactor;
  }
  p.surface_factor[i] = {real(g[0]), real(g[1]), real(g[2])};
}

// The factor on a bond along xi between particles with factors gi and gj (componentwise), times
// `scale` (the partial volume where it is folded in, below), as stored.
PD_HD inline uint16_t surface_bond_factor(Vec3 xi, Vec3 gi, Vec3 gj, real scale = real(1)) {
  const real gx = real(0.5) * (gi.x + gj.x), gy = real(0.5) * (gi.y + gj.y), gz = real(0.5) * (gi.z + gj.z);
  const real sum = xi.x * xi.x / (gx * gx) + xi.y * xi.y / (gy * gy) + xi.z * xi.z / (gz * gz);
  const double g = double(std::sqrt(dot(xi, xi) / sum)) * double(scale) / kSurfaceBondStep;
  return uint16_t(g < 65535.0 ? std::floor(g + 0.5) : 65535.0);
}

// Whether particle i's slots hold its bonds' factors with their partial volumes folded in, g beta
// (once the set-up has folded them, surface_bond_factors): a bond-based particle walked from its
// list (no lattice stencil). Its force loop then reads the product and takes the partial-volume
// rule at no bond (where the material has partial volumes off, as PMB has by default, the rule's
// test alone: bench/NOTES.md, the vase's springforces +2.5%, the torus's +4%); a lattice bond's
// stencil entry carries beta V_j already, and state-based loops take beta once per particle.
PD_HD inline bool folds_partial_volume(int32_t i, const BondsView& b, const Material& m) {
  return m.model != kStateBased && !(b.lattice.stencil && b.lattice.stencil[i] >= 0);
}

// Set-up, second pass (every particle's factors known, ghosts' included): each bond's factor at
// its slot; with `fold` (the set-up's last pass, after every reader of the plain factors:
// the rounds, the lattice rows, the stable step), times the bond's partial volume where
// folds_partial_volume. Where beta is 1 (no partial volumes, or a bond within delta - lambda/2)
// the stored value is the plain factor's.
PD_HD inline void surface_bond_factors(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                       bool fold = false) {
  const Material& m = mt.m[p.material[i]];
  const bool folds = fold && folds_partial_volume(i, b, m);
  const Vec3 x_i = xyz(p.rest[i]);
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int32_t j = bond_partner(b.neighbor[b.slot(i, k)]);
    const Vec3 xi = set_up_bond_vector(x_i, xyz(p.rest[j]), m);
    const real beta = folds ? volume_fraction(length(xi), m) : real(1);
    b.surface_bond[b.slot(i, k)] = surface_bond_factor(xi, p.surface_factor[i], p.surface_factor[j], beta);
  }
}

// The factor on the bond at `slot`, 1 where the run has no factors (then exactly the uncorrected
// bits): set-up, the energy, and the energy a breaking state-based bond releases (the force and
// dilatation kernels use surface_factor_of below, bond-based forces springforces.h's
// compile-time form). A listed bond-based particle's slot holds g beta (folds_partial_volume).
PD_HD inline real surface_bond_at(const BondsView& b, int64_t slot) {
  return b.surface_bond ? surface_bond_value(b.surface_bond[slot]) : real(1);
}

// Particle i's row of lattice bond factors (kSurface, a lattice particle of a run with rows;
// cuda/engine/lattice_families.h surface_rows), else null.
template <bool kSurface = true>
PD_HD inline const uint16_t* surface_row_of(const BondsView& b, int32_t i) {
  if constexpr (kSurface) {
    const ArrayView<const int32_t>& rows = b.lattice.surface_row;
    return rows.size > 0 && rows[i] >= 0 ? b.lattice.surface_table.data() + rows[i] : nullptr;
  } else {
    return nullptr;
  }
}

// The state-based kernels' factor on a bond: 1 without factors (first, the one test an
// uncorrected run makes, as in surface_bond_at), a lattice bond's from its particle's row (the
// same stored bits as at its slot, without the slot's index) else its slot's, a listed bond's
// from its slot, loaded ahead (SlotAhead).
template <class Geometry>
PD_HD inline real surface_factor_of(const BondsView& b, int64_t slot, const Geometry& g,
                                    const uint16_t* row) {
  if (!b.surface_bond) return real(1);
  if constexpr (std::is_same_v<Geometry, LatticeBondGeometry>)
    return surface_bond_value(row ? row[g.entry] : b.surface_bond[slot]);
  else
    return surface_bond_value(g.ahead.surface);
}

}  // namespace pd
