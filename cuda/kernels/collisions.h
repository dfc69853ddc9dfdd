// Kernel 3, `collisions`: quadratic repulsion between particles closer than the contact
// distance (Levine eq. 6): f_i = K_c (|x_i - x_j| - r_c)^2 (x_i - x_j)/|x_i - x_j|, with
// r_c = (lambda_i + lambda_j)/4, i.e. lambda/2 for equal spacings. Each particle reads its
// contact list (ContactView), which `collection` builds from the spatial hash only when some
// particle has moved most of its skin since the last build; between builds a step costs a read
// of the list, empty for a particle with nobody within reach (an intact lattice: neighbours at
// lambda, beyond the contact distance plus two skins at rest). Adds to the force `springforces`
// wrote.
#pragma once

#include "cuda/kernels/collection.h"
#include "cuda/views.h"

namespace pd {

// Skins, in units of the largest contact distance r_c. A particle at rest has 0.4: a pair at
// rest is listed within 1.8 r_c (0.9 lambda), so an intact lattice has no lists (bench/NOTES.md
// measured pairs of 0.3, 0.5 and 0.8). A moving particle's skin covers what it travels in
// kContactStepsAhead steps at its speed at the build, up to 1.6 (so that the wider search around
// fast particles stays within a few cells). A particle that has moved kContactTrigger of its skin
// triggers a build (all of it would do; the rest is a margin for the round-off of positions).
constexpr double kContactRestSkin = 0.4;
constexpr double kContactSkinCap = 1.6;
constexpr double kContactStepsAhead = 32;
constexpr double kContactTrigger = 0.9;
// Partners each list has room for at first (doubled for all when one overflows).
constexpr int32_t kContactCapacity = 8;

// The backend flags (Exec::flag) contact raises: a particle left its skin, more did than a
// relisting round keeps (position_update); a list outgrew its room, some list is not empty (the
// build). (Flags 3 and 4 are the bonds' breaking, bond_screen.h.)
enum ContactFlag : int { kFlagMoved = 0, kFlagOverflow = 1, kFlagPairs = 2, kFlagCrowded = 5 };
constexpr uint32_t kContactFlagMask = 0x7u | (1u << kFlagCrowded);

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

// visit(t) for every other sorted entry t within the contact distance plus `skin` of sorted entry
// s. The hash's cells are at least twice that reach for two skins at rest (the first build pass),
// so the 8-cell search sees every such entry.
template <class Visit>
PD_HD inline void for_each_contact_candidate(int32_t s, HashView h, real skin, Visit visit) {
  const Vec4 rs = h.record[s];
  for_each_record_within_half_cell(xyz(rs), h, [&](int32_t t, Vec4 rt) {
    if (t != s && within_contact_reach(rs, rt, skin)) visit(t);
  });
}

// A particle's skin for the lists built now: what it travels in kContactStepsAhead steps at
// velocity v relative to the lists' frame (contact_frame.h), between the skin at rest and the cap.
PD_HD inline real contact_skin(Vec3 v, const ContactView& c) {
  return std::fmin(c.cap, std::fmax(c.base, length(v - c.frame_velocity) * c.per_speed));
}

// Adds j to particle i's list (past its room: raises `overflow`, and the engine builds again
// with more room).
PD_HD inline void append_contact(int32_t i, int32_t j, ContactView c, int32_t* overflow) {
  const int32_t k = atomic_increment(&c.count[i]);
  if (k < c.capacity)
    c.partner[c.slot(i, k)] = j;
  else
    raise_flag(overflow);
}

// List build, pass 1 per sorted entry: the partners within the reach of two particles at rest
// (2 `base`), each particle's skin and the displacement its list is built at. A list with
// partners raises `pairs` (none anywhere: `collisions` is not launched).
PD_HD inline void build_contacts(int32_t s, ParticlesView p, HashView h, ContactView c, int32_t* overflow,
                                 int32_t* pairs) {
  const int32_t i = h.sorted[s];
  int32_t count = 0;
  for_each_contact_candidate(s, h, 2 * c.base, [&](int32_t t) {
    if (count < c.capacity) c.partner[c.slot(i, count)] = h.sorted[t];
    ++count;
  });
  c.count[i] = count;
  c.origin[i] = with_w(xyz(p.disp[i]) - c.shift, contact_skin(p.vel[i], c));
  if (count == 0) return;
  raise_flag(pairs);
  if (count > c.capacity) raise_flag(overflow);
}

// visit(cell) for every cell of the box of half side `radius` around x (the cells that hold
// every point within `radius` of x).
template <class Visit>
PD_HD inline void for_each_cell_in_box(Vec3 x, real radius, real inv_cell, Visit visit) {
  const Cell lo = cell_of(x - Vec3{radius, radius, radius}, inv_cell);
  const Cell hi = cell_of(x + Vec3{radius, radius, radius}, inv_cell);
  for (int32_t z = lo.z; z <= hi.z; ++z)
    for (int32_t y = lo.y; y <= hi.y; ++y)
      for (int32_t cx = lo.x; cx <= hi.x; ++cx) visit(Cell{cx, y, z});
}

// visit(t, record) for every sorted entry t whose record lies in cell nc.
template <class Visit>
PD_HD inline void for_each_record_in_cell(Cell nc, HashView h, Visit visit) {
  for_each_entry_in_bin(cell_bin(nc, h.bins), h, [&](int32_t t) {
    const Vec4 rt = h.record[t];
    if (same_cell(cell_of(xyz(rt), h.inv_cell), nc)) visit(t, rt);
  });
}

// Pass 2 per particle, for the particles whose skin exceeds the one at rest: the pairs beyond the
// first pass's reach but within the pair's contact distance plus both skins, added to both lists
// (between two such particles by the one of lower index, order_of). The search covers every cell within
// the largest such reach.
PD_HD inline void extend_contacts(int32_t f, ParticlesView p, HashView h, ContactView c,
                                  const MaterialTable& mt, real quarter_max, int32_t* overflow,
                                  int32_t* pairs) {
  const real skin_f = c.origin[f].w;
  if (!(skin_f > c.base)) return;
  const Vec4 rf = with_w(p.position(f), contact_quarter(f, p, mt));  // its hash record
  for_each_cell_in_box(xyz(rf), rf.w + quarter_max + skin_f + c.cap, h.inv_cell, [&](Cell nc) {
    for_each_record_in_cell(nc, h, [&](int32_t t, Vec4 rt) {
      const int32_t j = h.sorted[t];
      if (j == f || within_contact_reach(rf, rt, 2 * c.base)) return;  // listed by pass 1
      const real skin_j = c.origin[j].w;
      if (skin_j > c.base && order_of(p, j) < order_of(p, f)) return;  // listed from j
      if (!within_contact_reach(rf, rt, skin_f + skin_j)) return;
      append_contact(f, j, c, overflow);
      append_contact(j, f, c, overflow);
      raise_flag(pairs);
    });
  });
}

// Pass 3 per particle: its list sorted by index (order_of), so that its contact forces add up in
// one order whatever the hash and the appends did (CPU and GPU, a resumed run and an
// uninterrupted one, one rank or several).
PD_HD inline void sort_contacts(int32_t i, const ParticlesView& p, ContactView c) {
  const int32_t count = c.count[i];
  if (count > c.capacity) return;  // overflowed: built again
  for (int32_t k = 1; k < count; ++k) {
    const int32_t j = c.partner[c.slot(i, k)];
    const int32_t key = order_of(p, j);
    int32_t q = k;
    for (; q > 0 && order_of(p, c.partner[c.slot(i, q - 1)]) > key; --q)
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

// Whether displacement u, less the lists' frame's shift since their build, has moved farther than
// kContactTrigger of the particle's skin from where its list was built (origin: displacement less
// the shift then, skin; a non-finite u counts as moved).
PD_HD inline bool left_contact_skin(Vec4 u, Vec4 origin, Vec3 shift) {
  const real trigger = real(kContactTrigger) * origin.w;
  return !(length_squared(xyz(u) - shift - xyz(origin)) <= trigger * trigger);
}

// A particle that left its skin: raises `moved` and joins the movers (each counted, the first
// movers.size kept).
PD_HD inline void report_mover(int32_t i, const ContactView& c) {
  raise_flag(c.moved);
  if (!c.mover_count) return;
  const int32_t k = atomic_increment(c.mover_count);
  if (k < c.movers.size)
    c.movers[k] = i;
  else
    raise_flag(c.crowded);  // all lists are built: no relisting round is tried first
}

}  // namespace pd
