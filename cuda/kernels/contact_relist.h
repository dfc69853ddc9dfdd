// Contact lists rebuilt for the particles that left their skins alone (ContactLists::refresh),
// where they are few: in a fracture scene's later frames each build is set off by tens of
// particles (the vase after its impact: median 80 of 23,622), and building every list for them
// cost a third of the step (bench/NOTES.md).
//
// Why the lists stay complete: a pair missing from the lists was, when the later of its two
// lists was built, farther apart than its contact distance plus both skins, measured between
// where each particle stood at its own list's build (its origin). Neither has moved more than
// its skin from its origin since (else it would have triggered), so the pair is still beyond its
// contact distance. A mover's list is built from its new origin against every other particle's
// origin: the hash's records for the particles listed at the last full build, the relisted nodes
// (below) for those rebuilt since. Its new partners then get it in their lists (in index order),
// so that both particles of every pair in contact list each other; the pairs a mover left stay in
// its old partners' lists, beyond the contact distance, where they add exact zeros. The contact
// forces are therefore those of a full build to the last bit: the same pairs within the contact
// distance, added in the same order.
#pragma once

#include "cuda/kernels/collisions.h"

namespace pd {

// The particles relisted since the last full build, as nodes chained per bin of the contact hash
// (the bin of the cell their origin lies in): each relisting pushes a node, and a particle's
// latest node is the one that counts (older ones are skipped where met).
struct RelistView {
  ArrayView<int32_t> entry;            // per particle: its latest node + 1 (0: listed at the full build)
  ArrayView<int32_t> claimed;          // per particle: the last round it was relisted in (0: none)
  ArrayView<int32_t> head;             // per hash bin: the last node pushed into it, -1 for none
  ArrayView<int32_t> id, next, round;  // per node: the particle, the bin's node before, its round
  ArrayView<Vec4> record;              // per node: the origin's position, quarter contact spacing
  ArrayView<real> skin;                // per node: the skin
  ArrayView<int32_t> link;             // pairs (partner, mover): a mover to add to a partner's list
  int32_t* nodes = nullptr;            // nodes taken (past id.size: room ran out)
  int32_t* links = nullptr;            // pairs taken (past link.size / 2: room ran out)
};

// Mover t of this round, or -1 where t is past the movers, there were more than kept (then all
// lists are built again), or pass 1 found t repeating an earlier mover (relist_mover).
PD_HD inline int32_t round_mover(int32_t t, const ContactView& c) {
  const int32_t movers = *c.mover_count;
  if (movers > c.movers.size || t >= movers) return -1;
  return c.movers[t];
}

// Whether particle j was relisted in this round (it is a mover too).
PD_HD inline bool relisted_in(int32_t j, const RelistView& r, int32_t round) {
  const int32_t e = r.entry[j] - 1;
  return e >= 0 && r.round[e] == round;
}

// Pass 1 per mover: its new origin and skin in a new node, pushed into its cell's bin, and its
// list emptied. More nodes than room raise `rebuild` (a round never starts with more movers than
// kept: position_update raised kFlagCrowded, and the engine built all lists instead). A particle
// is named once per position_update, and every position_update is followed by a refresh; should
// it still be named twice, the mover that claims it second is struck from the round (-1), so
// that later passes skip it: a claim per particle, where a search of the earlier movers cost each
// of the first three passes a loop as long as the round (bench/NOTES.md).
PD_HD inline void relist_mover(int32_t t, ParticlesView p, HashView h, ContactView c, RelistView r,
                               const MaterialTable& mt, int32_t round, int32_t* rebuild) {
  const int32_t f = round_mover(t, c);
  if (f < 0) return;
  if (atomic_exchange(&r.claimed[f], round) == round) {
    c.movers[t] = -1;
    return;
  }
  const int32_t e = atomic_increment(r.nodes);
  if (e >= r.id.size) {
    raise_flag(rebuild);
    return;
  }
  const real skin = contact_skin(p.vel[f], c);
  const Vec4 record = with_w(p.position(f) - c.shift, contact_quarter(f, p, mt));  // in the lists' frame
  r.id[e] = f;
  r.record[e] = record;
  r.skin[e] = skin;
  r.round[e] = round;
  r.entry[f] = e + 1;
  c.origin[f] = with_w(xyz(p.disp[f]) - c.shift, skin);
  c.count[f] = 0;
  r.next[e] = atomic_exchange(&r.head[cell_bin(cell_of(xyz(record), h.inv_cell), h.bins)], e);
}

// Lanes per mover in pass 2: a mover's search box holds 27 to 64 cells, which one thread would
// walk in turn while the GPU, with threads for only tens of movers, idles (86 us a round against
// 22 with 32 lanes on the vase, bench/NOTES.md).
constexpr int32_t kRelistLanes = 32;

// Pass 2 per mover and lane: the particles whose origins lie within the pair's contact distance
// plus both skins of the mover's new origin, appended to its list (in no order; pass 3 sorts it)
// from the box's cells lane, lane + kRelistLanes, ...
PD_HD inline void gather_mover(int32_t g, HashView h, ContactView c, RelistView r, real quarter_max) {
  const int32_t f = round_mover(g / kRelistLanes, c), lane = g % kRelistLanes;
  if (f < 0 || r.entry[f] == 0) return;  // (no node: room ran out, all are built again)
  const int32_t e = r.entry[f] - 1;
  const Vec4 rf = r.record[e];
  const real skin_f = r.skin[e];
  const auto add = [&](int32_t j) {
    const int32_t k = atomic_increment(&c.count[f]);
    if (k < c.capacity) c.partner[c.slot(f, k)] = j;
  };
  const real radius = rf.w + quarter_max + skin_f + c.cap;
  const Cell lo = cell_of(xyz(rf) - Vec3{radius, radius, radius}, h.inv_cell);
  const Cell hi = cell_of(xyz(rf) + Vec3{radius, radius, radius}, h.inv_cell);
  const int32_t nx = hi.x - lo.x + 1, ny = hi.y - lo.y + 1, cells = nx * ny * (hi.z - lo.z + 1);
  for (int32_t q = lane; q < cells; q += kRelistLanes) {
    const Cell nc{lo.x + q % nx, lo.y + q / nx % ny, lo.z + q / (nx * ny)};
    // The particles listed at the last full build, at their origins (their hash records).
    for_each_record_in_cell(nc, h, [&](int32_t s, Vec4 rs) {
      const int32_t j = h.sorted[s];
      if (r.entry[j] == 0 && within_contact_reach(rf, rs, skin_f + c.origin[j].w)) add(j);
    });
    // Those relisted since (their latest nodes), at theirs.
    for (int32_t k = r.head[cell_bin(nc, h.bins)]; k >= 0; k = r.next[k]) {
      const int32_t j = r.id[k];
      const Vec4 rk = r.record[k];
      if (k == e || r.entry[j] != k + 1 || !same_cell(cell_of(xyz(rk), h.inv_cell), nc)) continue;
      if (within_contact_reach(rf, rk, skin_f + r.skin[k])) add(j);
    }
  }
}

// Whether j's list holds f.
PD_HD inline bool lists(int32_t j, int32_t f, const ContactView& c) {
  for (int32_t k = 0; k < c.count[j]; ++k)
    if (c.partner[c.slot(j, k)] == f) return true;
  return false;
}

// Pass 3 per mover: its list sorted (a list past its room raises `rebuild`), and the partners
// that did not move this round (those that did list it already) and do not list it yet, as pairs
// (partner, mover) for pass 4. Room run out raises `rebuild`.
PD_HD inline void finish_mover(int32_t t, const ParticlesView& p, ContactView c, RelistView r, int32_t round,
                               int32_t* rebuild, int32_t* pairs) {
  const int32_t f = round_mover(t, c);
  if (f < 0 || r.entry[f] == 0) return;  // all are built again
  const int32_t count = c.count[f];
  if (count > c.capacity) {
    raise_flag(rebuild);
    return;
  }
  if (count == 0) return;
  sort_contacts(f, p, c);
  raise_flag(pairs);
  for (int32_t k = 0; k < count; ++k) {
    const int32_t j = c.partner[c.slot(f, k)];
    if (relisted_in(j, r, round) || lists(j, f, c)) continue;
    const int32_t q = atomic_increment(r.links);
    if (2 * int64_t(q) + 1 >= r.link.size) {
      raise_flag(rebuild);
      return;
    }
    r.link[2 * q] = j;
    r.link[2 * q + 1] = f;
  }
}

// The pairs pass 3 asked for, past the room: none (all are built again).
PD_HD inline int32_t requested_links(const RelistView& r) {
  const int32_t links = *r.links;
  return 2 * int64_t(links) <= r.link.size ? links : 0;
}

// Pass 4 per pair: the mover appended to the partner's list (a full list raises `rebuild`).
PD_HD inline void add_link(int32_t q, ContactView c, RelistView r, int32_t* rebuild) {
  if (q >= requested_links(r)) return;
  const int32_t j = r.link[2 * q], f = r.link[2 * q + 1];
  const int32_t k = atomic_increment(&c.count[j]);
  if (k < c.capacity)
    c.partner[c.slot(j, k)] = f;
  else
    raise_flag(rebuild);
}

// Pass 5 per pair: the partner's list sorted again, by the first of its pairs.
PD_HD inline void sort_linked(int32_t q, const ParticlesView& p, ContactView c, RelistView r) {
  if (q >= requested_links(r)) return;
  const int32_t j = r.link[2 * q];
  for (int32_t s = 0; s < q; ++s)
    if (r.link[2 * s] == j) return;
  sort_contacts(j, p, c);
}

// After a full build: no particle relisted (their entries cleared by their nodes).
PD_HD inline void clear_relisted(int32_t e, RelistView r) {
  if (e < *r.nodes && e < r.id.size) r.entry[r.id[e]] = 0;
}

}  // namespace pd
