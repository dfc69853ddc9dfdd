// Kernel 3, `collisions`: quadratic repulsion between particles closer than the contact
// distance (Levine eq. 6): f_i = K_c (|x_i - x_j| - r_c)^2 (x_i - x_j)/|x_i - x_j|, with
// r_c = (lambda_i + lambda_j)/4, i.e. lambda/2 for equal spacings. Cells have the side of
// the largest spacing, twice the largest contact distance, so 8 cells hold every partner.
// Writes (not adds) the force, so it runs first among the force kernels. Runs over the hash's
// sorted records (position and quarter contact spacing per entry, written by `collection`).
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

// Sorted entry s of the hash (threads in bin order, so a warp's particles share cells): the
// contact force on its particle from every other particle within the contact distance.
PD_HD inline void collision_forces(int32_t s, ParticlesView p, HashView h, real stiffness) {
  const Vec4 ri = h.record[s];
  const Vec3 xi = xyz(ri);
  Vec3 f{0, 0, 0};
  for_each_record_within_half_cell(xi, h, [&](int32_t t, Vec4 rj) {
    if (t == s) return;
    f += contact_force(xi, xyz(rj), ri.w + rj.w, stiffness);
  });
  p.force[h.sorted[s]] = f;
}

}  // namespace pd
