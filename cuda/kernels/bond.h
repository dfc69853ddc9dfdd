// Per-bond quantities shared by the bond-based and state-based force kernels.
#pragma once

#include <type_traits>

#include "cuda/features.h"
#include "cuda/team.h"
#include "cuda/views.h"

namespace pd {

// Fraction of a neighbour's cube (side lambda) inside the horizon sphere, to first order:
// 1 up to delta - lambda/2, then falling linearly to 0 at delta + lambda/2 (1/2 at delta).
PD_HD inline real volume_fraction(real r0, const Material& m) {
  if (!m.partial_volumes) return real(1);
  const real half = real(0.5) * m.spacing;
  if (r0 <= m.horizon - half) return real(1);
  return fast_divide(m.horizon + half - r0, m.spacing);
}

// The same rule taken once per particle, for bond loops with registers to hold it: a bond up to
// `full_below` counts whole (every bond where the material has no partial volumes), else with
// (top - r0) / lambda, the same bits as volume_fraction (test BondGeometry.PartialVolumesAsTaken).
// The loop then tests one comparison per bond where reading the material's flag and horizon at
// every bond took five instructions: the state-based loops +3-4% (bench/NOTES.md). The
// bond-based ones, at 32-40 registers, keep the per-bond form.
struct PartialVolumes {
  real full_below, top, spacing;
};

PD_HD inline PartialVolumes partial_volumes_of(const Material& m) {
  const real half = real(0.5) * m.spacing;
  return {m.partial_volumes ? m.horizon - half : real(INFINITY), m.horizon + half, m.spacing};
}

PD_HD inline real volume_fraction(real r0, const PartialVolumes& v) {
  if (r0 <= v.full_below) return real(1);
  return fast_divide(v.top - r0, v.spacing);
}

// |y| - |xi| without cancellation: (|y|^2 - |xi|^2) / (|y| + |xi|) with
// |y|^2 - |xi|^2 = 2 xi.eta + eta.eta; `lengths_sum` is |y| + |xi| (bond_lengths_sum). Identical
// bits from both ends of a bond. The GPU's rounding is pinned (vec3.h pinned_dot).
PD_HD inline real bond_elongation(Vec3 xi, Vec3 eta, real lengths_sum) {
  return fast_divide(pinned_fma(real(2), pinned_dot(xi, eta), pinned_dot(eta, eta)), lengths_sum);
}

// |y| + |xi| from |y|^2, 1/|y| and |xi|: |y|'s product fused into the sum on the GPU.
PD_HD inline real bond_lengths_sum(real r2, real inv_r, real r0) {
  return pinned_fma(r2, inv_r, r0);
}

// Lengths of one bond and their reciprocals: reference |xi| and current |y| (0 when the two
// particles coincide, |y|^2 below kMinNormal, with reciprocal 0 so the bond exerts no force),
// and their sum (bond_elongation's).
struct BondLengths {
  real r0, inv_r0, r, inv_r, sum;
};

PD_HD inline BondLengths bond_lengths(Vec3 xi, Vec3 y) {
  BondLengths l;
  const real r02 = pinned_dot(xi, xi), r2 = pinned_dot(y, y);
  l.inv_r0 = fast_rsqrt(r02);
  l.r0 = pinned_product(r02, l.inv_r0);
  l.inv_r = r2 >= kMinNormal ? fast_rsqrt(r2) : real(0);
  l.r = r2 * l.inv_r;
  l.sum = bond_lengths_sum(r2, l.inv_r, l.r0);
  return l;
}

// A load from a stream each step reads once (explicit families' partner indices and surface
// factors): on the GPU marked evict-first, so that it does not push the partners' records, which
// the families read again and again, out of L1 and L2 (H200, bench/NOTES.md: the vase's and the
// torus's step +3%; the plastic histories read so lost 3.4% on the lattice, and are not).
template <class T>
PD_HD inline T load_streaming(const T& x) {
#if defined(__CUDA_ARCH__)
  return __ldcs(&x);
#else
  return x;
#endif
}

// A listed bond's surface factor, loaded a bond ahead with its partner index
// (for_each_intact_listed_bond): like the index it streams from DRAM, and each bond would
// otherwise wait for it in turn (bench/NOTES.md: +5-7% on the vase's and the torus's
// springforces). 0 in runs without factors, and a kernel that does not read it leaves its load
// out. (The strength of weakened bonds loaded ahead as well cost the 1M glass plate's explicit
// families 2.5% in one round: it is read at its slot.)
// The factor is held in 32 bits between its load and the visit: moving a 16-bit value between
// the loads ahead and the visit takes extra instructions a bond (one H200, bench/NOTES.md: the
// torus's step +1.0%, the plastic explicit lattice's +0.7%, the vase's springforces +0.6%).
struct SlotAhead {
  uint32_t surface = 0;  // BondsView::surface_bond
};

// kFactors: the caller knows the run has factors (the bond-based kSurface passes), and the load
// goes without the test of the array at every bond (two instructions a bond; bench/NOTES.md).
template <bool kFactors = false>
PD_HD inline SlotAhead slot_ahead(const BondsView& b, int64_t slot) {
  SlotAhead a;
  if (kFactors || b.surface_bond) a.surface = load_streaming(b.surface_bond[slot]);
  return a;
}

// A hint that the memory line holding `address` be brought into the L2 cache: no register, no
// fault, nothing to wait for; nothing on the CPU.
PD_HD inline void prefetch_line(const void* address) {
#if defined(__CUDA_ARCH__)
  asm volatile("prefetch.global.L2 [%0];" ::"l"(address));
#else
  (void)address;
#endif
}

// Which plastic histories a visitor reads: none, its own end's e^p (BondsView::plastic), or both
// ends' (plastic and plastic_mirror).
enum HistoryReads : int { kNoHistory = 0, kOwnHistory = 1, kBothHistories = 2 };

// Listed families: the histories a visitor reads at the next bond's slot, fetched into L2 with
// its partner index (the visit may store into them, which keeps the compiler from loading ahead).
template <int kHistory>
PD_HD inline void prefetch_history(const BondsView& b, int64_t slot) {
  if constexpr (kHistory != kNoHistory) prefetch_line(b.plastic.data() + slot);
  if constexpr (kHistory == kBothHistories) prefetch_line(b.plastic_mirror.data() + slot);
}

// Geometry of one bond at the current positions, with what the partner's records carry.
// weight(m) is beta V_j, the partner's volume inside the horizon: a lattice bond carries it from
// its stencil entry (kWeighted); a listed bond computes it where it is used, since computing it
// with the geometry keeps more registers live over the bond loop (56 against 48 for the glass
// plate's springforces, -27% speed: bench/NOTES.md).
template <bool kWeighted>
struct BondGeometryOf {
  Vec3 xi, y;
  real r0, inv_r0, r, inv_r, e;  // reference and current lengths (and reciprocals), extension
  real volume_j;                 // the partner's volume V_j (kWeighted: beta V_j)
  real tau_j;                    // the partner's effective strain limit
  bool weak;                     // the bond may carry a strength factor (BondsView::strength)
  int32_t entry;                 // kWeighted: the bond's stencil entry
  SlotAhead ahead;               // !kWeighted: what the bond's slot stores, loaded with its index
  template <class Rule>          // Material, or its PartialVolumes
  PD_HD real weight(const Rule& rule) const {
    if constexpr (kWeighted)
      return volume_j;
    else
      return volume_fraction(r0, rule) * volume_j;
  }
};
using BondGeometry = BondGeometryOf<false>;
using LatticeBondGeometry = BondGeometryOf<true>;

// A plastic visitor's e^p at a slot, 0 without loading it where `read` is false (the particle has
// none: reads_plastic_history, state_based.h). Lattice bonds only: listed loops load it anyway
// (a zero there), where the load made conditional cost the plastic explicit lattice's passes 6-8%
// (one H200, bench/NOTES.md).
template <class History, class Geometry>
PD_HD inline real plastic_at(const History& history, int64_t slot, bool read, const Geometry&) {
  if constexpr (std::is_same_v<Geometry, LatticeBondGeometry>)
    return read ? history[slot] : real(0);
  else
    return history[slot];
}

PD_HD inline BondGeometry bond_geometry(Vec4 rest_i, Vec4 disp_i, Vec4 rest_j, Vec4 disp_j,
                                        SlotAhead ahead = {}) {
  BondGeometry g;
  g.ahead = ahead;
  g.xi = xyz(rest_j) - xyz(rest_i);
  const Vec3 eta = xyz(disp_j) - xyz(disp_i);
  g.y = g.xi + eta;
  const BondLengths l = bond_lengths(g.xi, g.y);
  g.r0 = l.r0;
  g.inv_r0 = l.inv_r0;
  g.r = l.r;
  g.inv_r = l.inv_r;
  g.e = bond_elongation(g.xi, eta, l.sum);
  g.volume_j = rest_j.w;
  g.tau_j = disp_j.w;
  g.weak = true;
  g.entry = -1;
  return g;
}

// The factor on a bond's strain limit: its stored strength with kWeak (scenes that weaken bonds)
// where the geometry says it may have one, else 1 at no cost.
template <bool kWeak, class Geometry>
PD_HD inline real bond_strength(const BondsView& b, int64_t slot, const Geometry& g) {
  if constexpr (kWeak)
    return g.weak ? real(b.strength[slot]) * real(1.0 / 255) : real(1);
  else
    return real(1);
}

// Calls visit(slot, j, geometry) and returns whether the bond holds: a visitor that may break
// bonds returns bool (false: it broke now, and the caller records it), others return nothing.
template <class Visit, class Geometry>
PD_HD inline bool visit_bond(Visit& visit, int64_t slot, int32_t j, const Geometry& g) {
  if constexpr (std::is_same_v<decltype(visit(slot, j, g)), bool>) {
    return visit(slot, j, g);
  } else {
    visit(slot, j, g);
    return true;
  }
}

// How a listed family's loop loads the next bond's partner index a bond ahead, chosen by each
// visitor as measured (H200, bench/NOTES.md):
// - kWalkBranched: under a test that there is a next bond (teams, whose last bonds diverge anyway,
//   and the elastic state-based pass, whose registers fall out worse with the others);
// - kWalkClamped (one thread a particle): from slot first + min(k + 1, count - 1) kSliceWidth, so
//   after its last bond the family's last slot is read again, a value that goes unused, with no
//   branch, whose test, branch and convergence barrier were three of the ~67 instructions a bond
//   of the explicit bond-based lattice's pass (that pass +1.7%, the plastic one +2%); the passes
//   with weakened bonds or surface factors;
// - kWalkFromBase (one thread a particle): the same slot, its index's address one multiply-add on
//   the family's own base (three dependent instructions to the load where the clamped walk takes
//   six), and the bonds left intact counted as the count less those found or left broken (rare)
//   rather than at every bond; for the passes with neither weakened bonds nor factors (the
//   explicit bond-based lattice's pass +3.9%, the plastic one's +2%; with weakened bonds and
//   factors, the 1M glass plate's explicit families, -13%).
enum ListedWalk : int { kWalkBranched = 0, kWalkClamped = 1, kWalkFromBase = 2 };

// Explicit families: the next bond's partner index (and its surface factor, SlotAhead) is loaded
// before this bond is visited: a visit may break its own slot, which keeps the compiler from
// hoisting the next load over it, and without the early load every bond waits for two dependent
// loads in turn (index, then the partner's records). Measured on the H100 (bench/NOTES.md):
// +10-17% on springforces. A team's lane visits bonds lane, lane + kThreads, ... and returns the
// bonds it found intact. kHistory (HistoryReads): the plastic histories the visitor reads, fetched
// into L2 with the next index (prefetch_history: the plastic explicit lattice's step +12%). Slots
// are counted from the family's first (H200, bench/NOTES.md: springforces +7-11% on the vase,
// the torus and the explicit lattices). kFactors: slot_ahead's. kWalk: kWalkBranched or
// kWalkClamped (ListedWalk).
template <int kHistory, bool kFactors, int kWalk, int kThreads, class Visit>
PD_HD inline int32_t for_each_intact_listed_bond(int32_t i, const ParticlesView& p, const BondsView& b,
                                                 const Team<kThreads>& team, Visit& visit) {
  const Vec4 rest_i = p.rest[i], disp_i = p.disp[i];
  const int32_t count = b.count[i];
  int32_t holding = 0;
  const int32_t first = team.lane();
  // Slot k is first_slot + k kSliceWidth (BondsView::slot): the slice's offset read once, where
  // each bond would read it again (a visit's stores keep the compiler from hoisting the load).
  const int64_t first_slot = b.slot(i, 0);
  constexpr int64_t kStride = int64_t(kThreads) * kSliceWidth;
  int32_t next = 0;
  SlotAhead next_ahead;
  if (first < count) {
    const int64_t slot = first_slot + int64_t(first) * kSliceWidth;
    next = load_streaming(b.neighbor[slot]);
    next_ahead = slot_ahead<kFactors>(b, slot);
  }
  PD_BOND_LOOP
  for (int32_t k = first; k < count; k += kThreads) {
    const int64_t slot = first_slot + int64_t(k) * kSliceWidth;
    const int32_t j = next;
    const SlotAhead ahead = next_ahead;
    if constexpr (kWalk == kWalkClamped && kThreads == 1) {
      const int64_t next_slot = first_slot + int64_t(k + 1 < count ? k + 1 : k) * kSliceWidth;
      next = load_streaming(b.neighbor[next_slot]);
      next_ahead = slot_ahead<kFactors>(b, next_slot);
      prefetch_history<kHistory>(b, next_slot);
    } else if (k + kThreads < count) {
      const int64_t next_slot = slot + kStride;
      next = load_streaming(b.neighbor[next_slot]);
      next_ahead = slot_ahead<kFactors>(b, next_slot);
      prefetch_history<kHistory>(b, next_slot);
    }
    if (!bond_intact(j)) continue;
    if (visit_bond(visit, slot, j, bond_geometry(rest_i, disp_i, p.rest[j], p.disp[j], ahead)))
      ++holding;
    else
      b.neighbor[slot] = ~j;
  }
  return holding;
}

// The listed walk kWalkFromBase (ListedWalk), one thread a particle.
template <int kHistory, bool kFactors, class Visit>
PD_HD inline int32_t for_each_intact_listed_bond_from_base(int32_t i, const ParticlesView& p,
                                                           const BondsView& b, Visit& visit) {
  const Vec4 rest_i = p.rest[i], disp_i = p.disp[i];
  const int32_t count = b.count[i];
  if (count <= 0) return 0;
  const int64_t first_slot = b.slot(i, 0);
  const int32_t last = count - 1;
  const ArrayView<int32_t> family = b.neighbor.sub(first_slot, int64_t(last) * kSliceWidth + 1);
  int32_t next = load_streaming(family[0]);
  SlotAhead next_ahead = slot_ahead<kFactors>(b, first_slot);
  int32_t lost = 0;
  PD_BOND_LOOP
  for (int32_t k = 0; k <= last; ++k) {
    const int32_t j = next;
    const SlotAhead ahead = next_ahead;
    const int32_t k1 = k + 1;
    const int64_t ahead_k = int64_t(k1 < last ? k1 : last) * kSliceWidth;
    next = load_streaming(family[ahead_k]);
    next_ahead = slot_ahead<kFactors>(b, first_slot + ahead_k);
    prefetch_history<kHistory>(b, first_slot + ahead_k);
    if (!bond_intact(j)) {
      ++lost;
      continue;
    }
    const int64_t slot = first_slot + int64_t(k) * kSliceWidth;
    if (!visit_bond(visit, slot, j, bond_geometry(rest_i, disp_i, p.rest[j], p.disp[j], ahead))) {
      ++lost;
      b.neighbor[slot] = ~j;
    }
  }
  return last + 1 - lost;
}

// Geometry of a lattice bond: the reference vector, lengths and weight from the stencil entry.
PD_HD inline LatticeBondGeometry lattice_bond_geometry(const StencilEntry& s, Vec4 disp_i, Vec4 disp_j,
                                                       bool weak, int32_t entry) {
  LatticeBondGeometry g;
  g.xi = xyz(s.xi);
  const Vec3 eta = xyz(disp_j) - xyz(disp_i);
  g.y = g.xi + eta;
  const real r2 = pinned_dot(g.y, g.y);
  g.r0 = s.xi.w;
  g.inv_r0 = s.inv_r0;
  g.inv_r = r2 >= kMinNormal ? fast_rsqrt(r2) : real(0);
  g.r = r2 * g.inv_r;
  g.e = bond_elongation(g.xi, eta, bond_lengths_sum(r2, g.inv_r, g.r0));
  g.volume_j = s.weight;
  g.tau_j = disp_j.w;
  g.weak = weak;
  g.entry = entry;
  return g;
}

// Bits of x set (one instruction on the GPU).
PD_HD inline int32_t bit_count(uint32_t x) {
#if defined(__CUDA_ARCH__)
  return __popc(x);
#else
  return __builtin_popcount(x);
#endif
}

// Whether x holds in any thread of the warp that runs this together (on the CPU: x).
PD_HD inline bool warp_any(bool x) {
#if defined(__CUDA_ARCH__)
  return __any_sync(__activemask(), x);
#else
  return x;
#endif
}

// Visitors that read plastic histories (kHistory), one thread per particle: the histories' rows
// of a word's bonds fetched ahead into L2. A warp's particles share a slice (kSliceWidth = 32),
// whose row k (bond k of each) is one line of each history array; lane t fetches row k0 + t, so
// the warp asks for the word's rows at once where each bond would otherwise wait for its two rows
// from DRAM in turn (a visit may store into them, which keeps the compiler from loading ahead).
// Measured on the plastic lattice (H200, bench/NOTES.md): springforces +5%, the step +6%.
// fetch: whether any particle of the warp reads its histories (warp_any).
template <int kHistory, int kThreads>
PD_HD inline void prefetch_history_rows(int32_t i, int32_t k0, uint32_t present, const BondsView& b,
                                        bool fetch) {
#if defined(__CUDA_ARCH__)
  if constexpr (kHistory != kNoHistory && kThreads == 1) {
    const int32_t lane = int32_t(threadIdx.x % 32);
    if (!fetch) return;
    if (lane >= bit_count(present)) return;
    prefetch_history<kHistory>(b, b.slot(i, k0 + lane));
  }
#else
  (void)i, (void)k0, (void)present, (void)b, (void)fetch;
#endif
}

// Whether the lattice loop (below) walks a word's entries in runs of its unroll count, each
// run's bits shifted down once, so that each entry's tests take constant masks (one instruction
// where a shift by the entry's position takes three): on the GPU for visitors without plastic
// histories (one H200: the state-based lattice's springforces +2%, the 1M glass plate's +1.5%;
// in runs the plastic passes gained nothing and Chen's plastic wall's init lost 5%); not on the
// CPU, whose reference state-based lattice ran 8% slower in runs, and 2-4% slower in runs of 8
// entries each with its own shift (2-core CPU; bench/NOTES.md). Otherwise the word is one run.
template <int kHistory>
constexpr bool kLatticeRunBits =
#if defined(__CUDA_ARCH__)
    kHistory == kNoHistory;
#else
    false;
#endif

// Lattice families: the warp's threads walk the same stencil entries together (one broadcast
// load of the entry, partners at the same offset: one contiguous gather), each skipping the
// entries its intact bits leave out (intact bits are a subset of the present ones). A bond's
// slot is its position among the present entries, counted where a visitor uses it (breaking,
// weakened and plastic bonds), so the loop itself tests one bit per entry; the bonds still
// intact are counted from the bits after each word. kUnroll: the entry loop unrolled that many
// times, chosen per kernel as measured (bench/NOTES.md; 2 is what the compiler picks alone). A
// team's lane visits entries lane, lane + kThreads, ... of each word and counts the intact bonds
// among those. kHistory (HistoryReads): the plastic histories the visitor reads, fetched ahead
// (prefetch_history_rows) where any particle of the warp reads them (fetch_histories).
template <int kLattice, int kUnroll, int kHistory, int kThreads, class Visit,
          bool kRunBits = kLatticeRunBits<kHistory>>
PD_HD inline int32_t for_each_intact_lattice_bond(int32_t i, int32_t stencil, const ParticlesView& p,
                                                  const BondsView& b, const Team<kThreads>& team,
                                                  Visit& visit, bool fetch_histories) {
  constexpr int kEntries = 32 / kThreads;  // per lane and word
  constexpr int kEntryUnroll = kUnroll < kEntries ? kUnroll : kEntries;
  static_assert(kEntries % kEntryUnroll == 0, "runs of kEntryUnroll entries fill a word");
  const LatticeView& l = b.lattice;
  const Stencil st = l.stencils[stencil];
  const ArrayView<const StencilEntry> entries = l.entries.sub(st.first, st.size);
  const Vec4 disp_i = p.disp[i];
  const int64_t first_slot = b.slot(i, 0);
  int32_t k0 = 0;  // present bonds in the words before this one
  int32_t holding = 0;
  const bool fetch_rows = kHistory != kNoHistory && warp_any(fetch_histories);
  for (int32_t w0 = 0; w0 < st.size; w0 += 32) {
    const int64_t word = int64_t(w0 / 32) * b.n + i;
    const uint32_t present = l.present[word];
    uint32_t intact = l.intact[word];
    const uint32_t weak = l.weak ? l.weak[word] : 0u;
    prefetch_history_rows<kHistory, kThreads>(i, k0, present, b, fetch_rows);
    // A constant count, the bits past the stencil's end being 0: fewer registers (bench/NOTES.md).
    // The entries in runs of kEntryUnroll with kRunBits, else the word in one run; each run's bits
    // shifted down to its first entry once.
    constexpr int kRun = kRunBits ? kEntryUnroll : kEntries;
    PD_UNROLL(1)
    for (int32_t r0 = 0; r0 < kEntries; r0 += kRun) {
      const int32_t q0 = r0 * kThreads + team.lane();
      const uint32_t run_intact = intact >> q0, run_present = present >> q0, run_weak = weak >> q0;
      const int32_t run_k = k0 + bit_count(present & ((1u << q0) - 1u));  // present bonds before the run
      PD_UNROLL(kEntryUnroll)
      for (int32_t u = 0; u < kRun; ++u) {
        const int32_t shift = u * kThreads, q = q0 + shift;
        if (!((run_intact >> shift) & 1u)) continue;
        const StencilEntry& e = entries[w0 + q];
        const int32_t before = run_k + bit_count(run_present & ((1u << shift) - 1u));
        const int64_t slot = first_slot + int64_t(before) * kSliceWidth;
        int32_t j;
        if constexpr (kLattice == kLatticeOffsets)
          j = i + e.offset;
        else
          j = st.listed ? bond_partner(b.neighbor[slot]) : i + e.offset;
        if (!visit_bond(visit, slot, j,
                        lattice_bond_geometry(e, disp_i, p.disp[j], (run_weak >> shift) & 1u, w0 + q))) {
          b.neighbor[slot] = ~j;
          intact &= ~(1u << q);
          store_intact_word<kThreads>(&l.intact[word], intact, q);  // rare: stored at once
        }
      }
    }
    k0 += bit_count(present);
    holding += bit_count(intact & team.own_bits());
  }
  return holding;
}

// Calls visit(slot, j, geometry) for every intact bond of particle i, in storage order, and
// returns the bonds still intact after the visits. kLattice (LatticeMode, features.h): how
// lattice families are walked (kNoLattice: every family is read from its list, and the lattice
// loop is not compiled in); kUnroll and kHistory as for_each_intact_lattice_bond. With a team
// (team.h), each lane visits its share of the bonds and the count returned is the whole team's.
// fetch_histories: false where the visitor reads none of the particle's histories (the lattice
// loop's fetches of kHistory left out where no particle of the warp reads them). kFactors: the
// run has surface factors, known at compile time (slot_ahead); kWalk: how a listed family's loop
// loads ahead (ListedWalk).
template <int kLattice = kLatticeListed, int kUnroll = 2, int kHistory = kNoHistory, bool kFactors = false,
          int kWalk = kWalkBranched, int kThreads = 1, class Visit>
PD_HD inline int32_t for_each_intact_bond(int32_t i, const ParticlesView& p, const BondsView& b,
                                          const Team<kThreads>& team, Visit&& visit,
                                          bool fetch_histories = true) {
  const int32_t stencil = kLattice != kNoLattice && b.lattice.stencil ? b.lattice.stencil[i] : -1;
  if (kLattice != kNoLattice && stencil >= 0)
    return team.sum(for_each_intact_lattice_bond<kLattice, kUnroll, kHistory>(i, stencil, p, b, team, visit,
                                                                              fetch_histories));
  if constexpr (kWalk == kWalkFromBase && kThreads == 1)
    return for_each_intact_listed_bond_from_base<kHistory, kFactors>(i, p, b, visit);
  else
    return team.sum(for_each_intact_listed_bond<kHistory, kFactors, kWalk>(i, p, b, team, visit));
}
template <int kLattice = kLatticeListed, int kUnroll = 2, class Visit>
PD_HD inline int32_t for_each_intact_bond(int32_t i, const ParticlesView& p, const BondsView& b,
                                          Visit&& visit) {
  return for_each_intact_bond<kLattice, kUnroll>(i, p, b, Team<1>{}, visit);
}

}  // namespace pd
