// Per-bond quantities shared by the bond-based and state-based force kernels.
#pragma once

#include "../views.h"

namespace pd {

// Fraction of a neighbour's cube (side lambda) inside the horizon sphere, to first order:
// 1 up to delta - lambda/2, then falling linearly to 0 at delta + lambda/2 (1/2 at delta).
PD_HD inline real volume_fraction(real r0, const Material& m) {
  if (!m.partial_volumes) return real(1);
  const real half = real(0.5) * m.spacing;
  if (r0 <= m.horizon - half) return real(1);
  return (m.horizon + half - r0) * (real(1) / m.spacing);
}

// |y| - |xi| without cancellation: (|y|^2 - |xi|^2) / (|y| + |xi|) with
// |y|^2 - |xi|^2 = 2 xi.eta + eta.eta. Identical bits from both ends of a bond.
PD_HD inline real bond_elongation(Vec3 xi, Vec3 eta, real r0, real r) {
  return fast_divide(real(2) * dot(xi, eta) + dot(eta, eta), r + r0);
}

// Lengths of one bond and their reciprocals: reference |xi| and current |y| (0 when the two
// particles coincide, with reciprocal 0 so the bond exerts no force).
struct BondLengths {
  real r0, inv_r0, r, inv_r;
};

PD_HD inline BondLengths bond_lengths(Vec3 xi, Vec3 y) {
  BondLengths l;
  const real r02 = dot(xi, xi), r2 = dot(y, y);
  l.inv_r0 = fast_rsqrt(r02);
  l.r0 = r02 * l.inv_r0;
  l.inv_r = r2 > real(0) ? fast_rsqrt(r2) : real(0);
  l.r = r2 * l.inv_r;
  return l;
}

}  // namespace pd
