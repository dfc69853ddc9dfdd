// Family (bond list) construction on either backend: every pair of particles of the same
// body whose reference distance is at most the family radius of particle i (delta, or
// delta + lambda/2 with partial volumes). Two passes over
// a spatial hash of reference positions with cells of side >= delta: count, then fill.
// Families are then sorted by partner index, so they are identical on CPU and GPU.
#pragma once

#include "cuda/kernels/bond.h"
#include "cuda/kernels/collection.h"
#include "cuda/kernels/surface_correction.h"
#include "cuda/views.h"

namespace pd {

// Relative slack on the family radius (itself rounded to float) so that lattice points at exactly
// the radius survive its round-off.
constexpr double kHorizonSlack = 1e-6;
// The positions' round-off, relative to the largest coordinate magnitude of the two ends: each
// float coordinate lies within 2^-24 of its magnitude of the exact point, so a difference's length
// is off by at most sqrt(3) 2^-24 times the two magnitudes' sum; 2^-22 keeps a margin.
constexpr double kPositionSlack = 0x1p-22;

// The largest magnitude among a position's coordinates.
PD_HD inline double largest_coordinate(Vec3 x) {
  return fmax(fabs(double(x.x)), fmax(fabs(double(x.y)), fabs(double(x.z))));
}

// The largest reference distance of a bond between particles at `a` and `b` whose family radius is
// `radius`: so that lattice points at exactly the radius are partners wherever the body sits (a
// relative slack alone dropped them a few spacings from the origin: at 0.16 m with a 1 mm spacing
// the positions' round-off is 2e-6 of delta). The same from both ends.
PD_HD inline double family_reach(double radius, Vec3 a, Vec3 b) {
  return radius * (1.0 + kHorizonSlack) + kPositionSlack * (largest_coordinate(a) + largest_coordinate(b));
}

template <class Visit>
PD_HD inline void for_each_family_member(int32_t i, ParticlesView p, HashView h, const MaterialTable& mt,
                                         Visit visit) {
  const Vec3 xi = xyz(p.rest[i]);
  const double radius = double(mt.m[p.material[i]].family_radius());
  const int32_t body = p.body[i];
  auto pos = [&](int32_t j) { return xyz(p.rest[j]); };
  for_each_nearby(xi, h, pos, [&](int32_t j) {
    if (j == i || p.body[j] != body) return;
    const Vec3 xj = xyz(p.rest[j]);
    const double dx = double(xj.x) - xi.x, dy = double(xj.y) - xi.y, dz = double(xj.z) - xi.z;
    const double reach = family_reach(radius, xi, xj);
    if (dx * dx + dy * dy + dz * dz <= reach * reach) visit(j);
  });
}

PD_HD inline void count_family(int32_t i, ParticlesView p, HashView h, const MaterialTable& mt,
                               int32_t* count) {
  int32_t c = 0;
  for_each_family_member(i, p, h, mt, [&](int32_t) { ++c; });
  count[i] = c;
}

// Storage each slice of kSliceWidth particles needs: width x its longest family.
PD_HD inline void slice_length(int32_t s, int32_t n, const int32_t* count, int64_t* length) {
  int32_t longest = 0;
  for (int32_t i = s * kSliceWidth; i < n && i < (s + 1) * kSliceWidth; ++i)
    longest = count[i] > longest ? count[i] : longest;
  length[s] = int64_t(longest) * kSliceWidth;
}

PD_HD inline void fill_family(int32_t i, ParticlesView p, HashView h, const MaterialTable& mt, BondsView b) {
  int32_t k = 0;
  for_each_family_member(i, p, h, mt, [&](int32_t j) { b.neighbor[b.slot(i, k++)] = j; });
}

// Families are kept in ascending partner order (order_of; an insertion sort of the few hundred
// slots, once at set-up): the order lattice families walk their stencils in
// (host/lattice_families.h).
PD_HD inline void sort_family(int32_t i, const ParticlesView& p, BondsView b) {
  for (int32_t k = 1; k < b.count[i]; ++k) {
    const int32_t j = b.neighbor[b.slot(i, k)];
    const int32_t key = order_of(p, j);
    int32_t q = k;
    for (; q > 0 && order_of(p, b.neighbor[b.slot(i, q - 1)]) > key; --q)
      b.neighbor[b.slot(i, q)] = b.neighbor[b.slot(i, q - 1)];
    b.neighbor[b.slot(i, q)] = j;
  }
}

// Position of the bond to particle i in the family of j (-1 when j has none): families are in
// ascending partner order (sort_family), so a bisection.
PD_HD inline int32_t position_in_family(const BondsView& b, int32_t j, int32_t i) {
  int32_t lo = 0, hi = b.count[j];
  while (lo < hi) {
    const int32_t mid = (lo + hi) / 2;
    if (bond_partner(b.neighbor[b.slot(j, mid)]) < i)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < b.count[j] && bond_partner(b.neighbor[b.slot(j, lo)]) == i ? lo : -1;
}

// The Silling & Askari (2005, eq. 29) stability rate of particle i over its family as built:
// sum_j g_ij beta V_j c / |xi_j| / rho_i, so that dt_c,i = sqrt(2 / rate) (g_ij the surface
// correction's factor on the bond, 1 without it). State-based materials use
// the micromodulus of the PMB material with the same P-wave modulus, c = 18 K' / (pi delta^4),
// K' = (K + 4 mu / 3) / 1.8 (PMB's own P-wave modulus is 1.8 K), as host/material.h's estimate.
// collider_stiffness: the largest penalty collider stiffness K (colliders.h), whose push
// K V^(1/3) on a particle of mass m adds K V^(1/3) / m.
PD_HD inline double stability_rate(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                   double collider_stiffness) {
  const Material& m = mt.m[p.material[i]];
  double c = double(m.micromodulus);
  if (m.model == kStateBased) {
    const double k_eq = (double(m.bulk_modulus) + 4.0 * double(m.shear_modulus) / 3.0) / 1.8;
    const double d = double(m.horizon);
    c = 18.0 * k_eq / (3.14159265358979323846 * d * d * d * d);
  }
  double sum = 0;
  for (int32_t k = 0; k < b.count[i]; ++k) {
    const int32_t j = bond_partner(b.neighbor[b.slot(i, k)]);
    const real r0 = length(xyz(p.rest[j]) - xyz(p.rest[i]));
    sum += double(surface_bond_at(b, b.slot(i, k))) * double(volume_fraction(r0, m)) * double(p.volume(j)) *
           c / double(r0);
  }
  return (sum * double(p.volume(i)) + collider_stiffness * std::cbrt(double(p.volume(i)))) *
         double(p.inv_mass[i]);
}

}  // namespace pd
