// Kernel 3, `collisions`: quadratic repulsion between particles closer than the contact
// distance (Levine eq. 6): f_i = K_c (|x_i - x_j| - r_c)^2 (x_i - x_j)/|x_i - x_j|, with
// r_c = (lambda_i + lambda_j)/4, i.e. lambda/2 for equal spacings. Each particle reads its
// contact list (ContactView), which `collection` builds from the spatial hash only when some
// particle has moved more than about half the skin since the last build; between builds a step
// costs a read of the list, empty for a particle with nobody within reach (an intact lattice:
// neighbours at lambda, beyond the contact distance plus the skin). Adds to the force
// `springforces` wrote.
#pragma once

#include "../views.h"
#include "collection.h"

namespace pd {

// The skin of the contact lists as a fraction of the largest contact distance r_c: lists reach
// 1.8 r_c (0.9 lambda), so an intact lattice has none (bench/NOTES.md measured 0.3, 0.5 and
// 0.8). A particle that has moved more than 0.45 of the skin triggers a rebuild (half the skin
// would do; the rest is a margin for the round-off of float positions).
constexpr double kContactSkin = 0.8;
constexpr double kContactTrigger = 0.45;
// Partners each list has room for at first (doubled for all when one overflows).
constexpr int32_t kContactCapacity = 8;

// The backend flags (Exec::flag) contact raises: a particle left its skin (position_update); a
// list outgrew its room, some list is not empty (build_contacts).
enum ContactFlag : int { kFlagMoved = 0, kFlagOverflow = 1, kFlagPairs = 2 };

PD_HD inline Vec3 contact_force(Vec3 xi, Vec3 xj, real contact_distance, real stiffness) {
  const Vec3 d = xi - xj;
  const real r2 = length_squared(d);
  if (!(r2 < contact_distance * contact_distance) || r2 <= real(0)) return {0, 0, 0};
  const real r = std::sqrt(r2);
  const real gap = r - contact_distance;
  return (stiffness * gap * gap / r) * d;
}

// A quarter of particle i's contact spacing: the contact distance of a pair is the sum of theirs.
PD_HD inline real contact_quarter(int32_t i, const ParticlesView& p, const MaterialTable& mt) {
  return real(0.25) * mt.m[p.material[i]].contact_spacing;
}

// Whether two hash records (position, quarter contact spacing) are within the contact distance
// plus the skin: the pairs the lists keep. Symmetric to the last bit.
PD_HD inline bool within_contact_reach(Vec4 a, Vec4 b, real skin) {
  const real reach = a.w + b.w + skin;
  return length_squared(xyz(a) - xyz(b)) < reach * reach;
}

// visit(t) for every other sorted entry t within reach of sorted entry s. The hash's cells are
// at least twice the largest reach, so the 8-cell search sees every such entry.
template <class Visit>
PD_HD inline void for_each_contact_candidate(int32_t s, HashView h, real skin, Visit visit) {
  const Vec4 rs = h.record[s];
  for_each_record_within_half_cell(xyz(rs), h, [&](int32_t t, Vec4 rt) {
    if (t != s && within_contact_reach(rs, rt, skin)) visit(t);
  });
}

// List build, per sorted entry: the particle's partners (up to the capacity; more raise
// `overflow`, and the engine builds again with room for more), sorted by index so that its
// contact forces add up in one order whatever the hash did (CPU and GPU, a resumed run and an
// uninterrupted one), and the displacement the list is built at. A list with partners raises
// `pairs` (none anywhere: `collisions` is not launched).
PD_HD inline void build_contacts(int32_t s, ParticlesView p, HashView h, ContactView c, int32_t* overflow,
                                 int32_t* pairs) {
  const int32_t i = h.sorted[s];
  int32_t count = 0;
  for_each_contact_candidate(s, h, c.skin, [&](int32_t t) {
    if (count < c.capacity) c.partner[c.slot(i, count)] = h.sorted[t];
    ++count;
  });
  c.count[i] = count;
  c.origin[i] = p.disp[i];
  if (count == 0) return;
  raise_flag(pairs);
  if (count > c.capacity) return raise_flag(overflow);
  for (int32_t k = 1; k < count; ++k) {
    const int32_t j = c.partner[c.slot(i, k)];
    int32_t q = k;
    for (; q > 0 && c.partner[c.slot(i, q - 1)] > j; --q)
      c.partner[c.slot(i, q)] = c.partner[c.slot(i, q - 1)];
    c.partner[c.slot(i, q)] = j;
  }
}

// Per particle: the contact forces from its list, added to the force on it.
PD_HD inline void collision_forces(int32_t i, ParticlesView p, ContactView c, const MaterialTable& mt,
                                   real stiffness) {
  const int32_t count = c.count[i];
  if (count == 0) return;
  const Vec3 xi = p.position(i);
  const real quarter_i = contact_quarter(i, p, mt);
  Vec3 f{0, 0, 0};
  for (int32_t k = 0; k < count; ++k) {
    const int32_t j = c.partner[c.slot(i, k)];
    f += contact_force(xi, p.position(j), quarter_i + contact_quarter(j, p, mt), stiffness);
  }
  p.force[i] = p.force[i] + f;
}

// Whether displacement u has moved farther than the trigger from where the lists were built
// (a non-finite one counts as moved).
PD_HD inline bool left_contact_skin(Vec4 u, Vec4 origin, real trigger) {
  return !(length_squared(xyz(u) - xyz(origin)) <= trigger * trigger);
}

}  // namespace pd
