// Bond loops (cuda/kernels/bond.h): the listed family's three walks (ListedWalk) visit the same
// bonds with the same geometry, break the same ones and count the same bonds left intact; so do
// the lattice loop's two ways of walking a word's entries (kLatticeRunBits: in runs of the unroll
// count, or the word in one run).
#include <gtest/gtest.h>

#include <vector>

#include "cuda/kernels/bond.h"
#include "tests/support/particle_arrays.h"

namespace pd {
namespace {

// Five particles in one slice with families of 0, 1, 4, 3 and 2 bonds; bond 1 of particle 2 and
// bond 0 of particle 4 already broken (stored as ~j).
struct Families : testing::ParticleArrays {
  std::vector<int32_t> count{0, 1, 4, 3, 2}, neighbor;
  std::vector<int64_t> offset{0};

  Families() {
    for (int i = 0; i < 5; ++i) {
      rest.push_back({real(i), real(0.5 * i * i), real(-i), real(1 + i)});
      disp.push_back({real(1e-3 * i), real(-2e-3 * i), real(5e-4), real(0.1)});
    }
    neighbor.assign(4 * kSliceWidth, 0);
    const std::vector<std::vector<int32_t>> lists{{}, {2}, {0, ~1, 3, 4}, {1, 2, 4}, {~2, 3}};
    for (int i = 0; i < 5; ++i)
      for (size_t k = 0; k < lists[i].size(); ++k) neighbor[k * kSliceWidth + i] = lists[i][k];
  }
  BondsView bonds() {
    BondsView b;
    b.n = 5;
    b.slice_offset = view_of(offset);
    b.count = view_of(count);
    b.neighbor = view_of(neighbor);
    return b;
  }
};

struct Visit {
  int64_t slot;
  int32_t j;
  real e;
  bool operator==(const Visit& o) const { return slot == o.slot && j == o.j && e == o.e; }
};

// Walks every particle's family with kWalk; the visitor breaks each bond to particle 3 (returns
// false). Returns the visits, and fills the counts and the stored partners after the walk.
template <int kWalk>
std::vector<Visit> walk(std::vector<int32_t>& intact, std::vector<int32_t>& stored) {
  Families f;
  std::vector<Visit> visits;
  intact.clear();
  for (int32_t i = 0; i < 5; ++i)
    intact.push_back(for_each_intact_bond<kNoLattice, 2, kNoHistory, false, kWalk>(
        i, f.view(), f.bonds(), Team<1>{}, [&](int64_t slot, int32_t j, const auto& g) {
          visits.push_back({slot, j, g.e});
          return j != 3;
        }));
  stored = f.neighbor;
  return visits;
}

TEST(ListedWalk, EveryWalkVisitsBreaksAndCountsTheSameBonds) {
  std::vector<int32_t> intact_b, intact_c, intact_f, stored_b, stored_c, stored_f;
  const std::vector<Visit> branched = walk<kWalkBranched>(intact_b, stored_b);
  const std::vector<Visit> clamped = walk<kWalkClamped>(intact_c, stored_c);
  const std::vector<Visit> from_base = walk<kWalkFromBase>(intact_f, stored_f);
  // The intact bonds, in storage order: 1->2; 2->0, 2->3, 2->4; 3->1, 3->2, 3->4; 4->3.
  ASSERT_EQ(branched.size(), 8u);
  EXPECT_EQ(branched[0].j, 2);
  EXPECT_EQ(branched[2].slot, 2 * kSliceWidth + 2);  // particle 2's bond 2 (bond 1 broken)
  EXPECT_EQ(branched[7].slot, 1 * kSliceWidth + 4);  // particle 4's bond 1
  EXPECT_EQ(clamped, branched);
  EXPECT_EQ(from_base, branched);
  // Left intact: particle 2 loses its bond to 3, particle 4 its bond to 3 as well.
  EXPECT_EQ(intact_b, (std::vector<int32_t>{0, 1, 2, 3, 0}));
  EXPECT_EQ(intact_c, intact_b);
  EXPECT_EQ(intact_f, intact_b);
  EXPECT_EQ(stored_b[2 * kSliceWidth + 2], ~3);
  EXPECT_EQ(stored_b[1 * kSliceWidth + 4], ~3);
  EXPECT_EQ(stored_c, stored_b);
  EXPECT_EQ(stored_f, stored_b);
}

// A row of 100 particles on one stencil of 44 entries (offsets -20 to 24 but 0: two mask words),
// some entries absent (cut), some bonds already broken, some weakened.
struct LatticeRow : testing::ParticleArrays {
  static constexpr int32_t kN = 100, kEntries = 44, kWords = 2;
  std::vector<int32_t> count, neighbor;
  std::vector<int64_t> offset;
  std::vector<int16_t> stencil_of;
  std::vector<Stencil> stencils{{0, kEntries, 0}};
  std::vector<StencilEntry> entries;
  std::vector<uint32_t> present, intact_bits, weak;

  LatticeRow() {
    for (int32_t i = 0; i < kN; ++i) {
      rest.push_back({real(i), 0, 0, real(1)});
      disp.push_back({real(1e-3 * (i % 7)), real(-2e-4 * (i % 5)), real(1e-4 * (i % 3)), real(0.1)});
    }
    for (int32_t o = -20; o <= 24; ++o)
      if (o != 0)
        entries.push_back({{real(o), 0, 0, real(std::abs(o))}, real(1) / real(std::abs(o)), 1, o, 0});
    stencil_of.assign(kN, 0);
    for (int32_t s = 0; s * kSliceWidth < kN; ++s) offset.push_back(int64_t(s) * kEntries * kSliceWidth);
    neighbor.assign(offset.size() * kEntries * kSliceWidth, 0);
    present.assign(kWords * kN, 0u);
    intact_bits.assign(kWords * kN, 0u);
    weak.assign(kWords * kN, 0u);
    for (int32_t i = 0; i < kN; ++i) {
      int32_t k = 0;
      for (int32_t q = 0; q < kEntries; ++q) {
        const int32_t j = i + entries[size_t(q)].offset;
        if (j < 0 || j >= kN || (i * 7 + q) % 11 == 0) continue;  // outside the row, or cut
        const size_t word = size_t(q / 32) * kN + size_t(i), bit = size_t(q % 32);
        present[word] |= 1u << bit;
        if ((i + 3 * q) % 13 != 0) intact_bits[word] |= 1u << bit;  // else broken before
        if ((i * q) % 5 == 1) weak[word] |= 1u << bit;
        neighbor[size_t(offset[size_t(i / kSliceWidth)] + int64_t(k) * kSliceWidth + i % kSliceWidth)] = j;
        ++k;
      }
      count.push_back(k);
    }
  }
  BondsView bonds() {
    BondsView b;
    b.n = kN;
    b.slice_offset = view_of(offset);
    b.count = view_of(count);
    b.neighbor = view_of(neighbor);
    b.lattice.words = kWords;
    b.lattice.stencil = view_of(stencil_of);
    b.lattice.stencils = view_of(stencils);
    b.lattice.entries = view_of(entries);
    b.lattice.present = view_of(present);
    b.lattice.intact = view_of(intact_bits);
    b.lattice.weak = view_of(weak);
    return b;
  }
};

struct LatticeVisit {
  int64_t slot;
  int32_t j, entry;
  bool weak;
  real e;
  bool operator==(const LatticeVisit& o) const {
    return slot == o.slot && j == o.j && entry == o.entry && weak == o.weak && e == o.e;
  }
};

// Records each visit; breaks the bonds whose partner and entry sum to a multiple of 7.
struct LatticeRecorder {
  std::vector<LatticeVisit>* visits;
  template <class Geometry>
  bool operator()(int64_t slot, int32_t j, const Geometry& g) const {
    visits->push_back({slot, j, g.entry, g.weak, g.e});
    return (j + g.entry) % 7 != 0;
  }
};

// Walks every particle's lattice family in runs of kUnroll entries (kRunBits) or a word in one
// run, unrolled kUnroll times. Fills the counts left intact and the bits and
// partners stored after the walk.
template <bool kRunBits, int kUnroll>
std::vector<LatticeVisit> walk_lattice(std::vector<int32_t>& holding, std::vector<uint32_t>& bits,
                                       std::vector<int32_t>& stored) {
  LatticeRow row;
  std::vector<LatticeVisit> visits;
  LatticeRecorder record{&visits};
  holding.clear();
  for (int32_t i = 0; i < LatticeRow::kN; ++i)
    holding.push_back(
        for_each_intact_lattice_bond<kLatticeOffsets, kUnroll, kNoHistory, 1, LatticeRecorder, kRunBits>(
            i, 0, row.view(), row.bonds(), Team<1>{}, record, true));
  bits = row.intact_bits;
  stored = row.neighbor;
  return visits;
}

TEST(LatticeLoop, RunsAndWholeWordsVisitBreakAndCountTheSameBonds) {
  std::vector<int32_t> holding_runs, holding_entries, holding_two, stored_runs, stored_entries, stored_two;
  std::vector<uint32_t> bits_runs, bits_entries, bits_two;
  const auto runs = walk_lattice<true, 8>(holding_runs, bits_runs, stored_runs);
  const auto entries = walk_lattice<false, 8>(holding_entries, bits_entries, stored_entries);
  const auto two = walk_lattice<true, 2>(holding_two, bits_two, stored_two);
  // Every present, intact bond visited once, in entry order, with its slot, weak bit and entry.
  const LatticeRow row;
  size_t expected = 0, weak_visits = 0, breaks = 0;
  for (int32_t i = 0; i < LatticeRow::kN; ++i)
    for (int32_t w = 0; w < LatticeRow::kWords; ++w)
      expected += size_t(bit_count(row.intact_bits[size_t(w) * LatticeRow::kN + size_t(i)]));
  ASSERT_EQ(runs.size(), expected);
  for (const LatticeVisit& v : runs) {
    weak_visits += v.weak;
    breaks += (v.j + v.entry) % 7 == 0;
    const int32_t i = v.j - row.entries[size_t(v.entry)].offset;
    EXPECT_EQ(row.neighbor[size_t(v.slot)], v.j) << "particle " << i << " entry " << v.entry;
  }
  EXPECT_GT(weak_visits, 0u);
  EXPECT_GT(breaks, 0u);
  EXPECT_EQ(entries, runs);
  EXPECT_EQ(two, runs);
  EXPECT_EQ(holding_entries, holding_runs);
  EXPECT_EQ(holding_two, holding_runs);
  EXPECT_EQ(bits_entries, bits_runs);
  EXPECT_EQ(bits_two, bits_runs);
  EXPECT_EQ(stored_entries, stored_runs);
  EXPECT_EQ(stored_two, stored_runs);
  // What the loop left: the broken bonds' bits cleared and their partners stored as ~j.
  size_t left = 0;
  for (int32_t h : holding_runs) left += size_t(h);
  EXPECT_EQ(left, expected - breaks);
}

}  // namespace
}  // namespace pd
