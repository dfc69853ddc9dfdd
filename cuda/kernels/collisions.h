// Kernel 3, `collisions`: quadratic repulsion between particles closer than the contact
// distance (Levine eq. 6): f_i = K_c (|x_i - x_j| - r_c)^2 (x_i - x_j)/|x_i - x_j|, with
// r_c = (lambda_i + lambda_j)/4, i.e. lambda/2 for equal spacings. Cells have the side of
// the largest spacing, twice the largest contact distance, so 8 cells hold every partner.
// Writes (not adds) the force, so it runs first among the force kernels.
#pragma once

#include "../views.h"
#include "collection.h"

namespace pd {

PD_HD inline Vec3 contact_force(Vec3 xi, Vec3 xj, real contact_distance, real stiffness) {
  const Vec3 d = xi - xj;
  const real r2 = length_squared(d);
  if (!(r2 < contact_distance * contact_distance) || r2 <= real(0)) return {0, 0, 0};
  const real r = std::sqrt(r2);
  const real gap = r - contact_distance;
  return (stiffness * gap * gap / r) * d;
}

PD_HD inline void collision_forces(int32_t i, ParticlesView p, HashView h, const MaterialTable& mt,
                                   real stiffness) {
  auto pos = [&](int32_t j) { return p.position(j); };
  const Vec3 xi = pos(i);
  const real quarter_i = real(0.25) * mt.m[p.material[i]].contact_spacing;
  Vec3 f{0, 0, 0};
  for_each_within_half_cell(xi, h, pos, [&](int32_t j) {
    if (j == i) return;
    const real rc = quarter_i + real(0.25) * mt.m[p.material[j]].contact_spacing;
    f += contact_force(xi, pos(j), rc, stiffness);
  });
  p.force[i] = f;
}

}  // namespace pd
