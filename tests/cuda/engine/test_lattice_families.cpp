// Lattice families (host/lattice_families.h): which bodies find their partners by offset, their
// stencils and bits, and that the engine computes the same motion with them as with explicit
// families (CPU-reference backend; the GPU runs the same kernel bodies, tests/gpu).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "cuda/engine/bond_cuts.h"
#include "cuda/engine/engine.h"
#include "cuda/engine/lattice_families.h"
#include "cuda/parallel/partition.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

using testing::lattice_block;
using testing::state_block;

// A power-of-two spacing puts every grid point exactly on a float, so an explicit bond vector
// (the difference of two positions) is the stencil's exactly; what is left between the two
// paths is the rounding of |xi| and 1/|xi| (float against double), a few ulps.
constexpr double kLambda = 0x1p-10;

BondLists bonds_of(const SimulationInput& in) {
  BondLists b;
  make_cpu_engine(in)->read_bonds(b);
  return b;
}

bool bit(const LatticeFamilies& lf, const std::vector<uint32_t>& mask, int32_t i, int32_t q) {
  return mask[size_t(q / 32) * lf.stencil.size() + size_t(i)] >> (q % 32) & 1u;
}

TEST(LatticeFamilies, BoxGridBodyGetsItsStencil) {
  const auto in = lattice_block(10, 9, 8, 1e-3);  // delta = 3 lambda with partial volumes
  const BondLists b = bonds_of(in);
  const LatticeFamilies lf = lattice_families(in.particles, in.materials, b);
  ASSERT_EQ(lf.stencils.size(), 1u);
  EXPECT_EQ(lf.particles(), int64_t(in.particles.size()));
  const Stencil& st = lf.stencils[0];
  EXPECT_EQ(st.size, 178);  // the cubes overlapping the horizon sphere: |d| <= 3.5 lambda
  EXPECT_EQ(lf.words, 6);
  // An interior particle holds every entry; partners at the offsets, bond vectors as the
  // positions say, ascending offsets.
  const int32_t i = 4 + 10 * (4 + 9 * 4);
  for (int32_t q = 0; q < st.size; ++q) {
    const StencilEntry& e = lf.entries[size_t(st.first + q)];
    EXPECT_TRUE(bit(lf, lf.present, i, q));
    EXPECT_TRUE(bit(lf, lf.intact, i, q));
    if (q > 0) {
      EXPECT_LT(lf.entries[size_t(st.first + q - 1)].offset, e.offset);
    }
    const Vec3 d = in.particles.rest[size_t(i + e.offset)] - in.particles.rest[size_t(i)];
    EXPECT_NEAR(d.x, e.xi.x, 1e-9);
    EXPECT_NEAR(d.y, e.xi.y, 1e-9);
    EXPECT_NEAR(d.z, e.xi.z, 1e-9);
    EXPECT_NEAR(e.xi.w, length(xyz(e.xi)), 1e-9);
    EXPECT_NEAR(e.xi.w * e.inv_r0, 1.0, 1e-6);
    // beta V_j: whole cubes well inside the horizon, the overlapped fraction at its edge.
    const double beta = std::min(1.0, std::max(0.0, (3.5e-3 - e.xi.w) / 1e-3));
    EXPECT_NEAR(e.weight / in.particles.volume[0], beta, 1e-5) << q;
  }
  // Every particle's present bits, walked in order, are its listed partners.
  const BondsView v = b.view();
  for (int32_t p = 0; p < v.n; ++p) {
    int32_t k = 0;
    for (int32_t q = 0; q < st.size; ++q) {
      if (!bit(lf, lf.present, p, q)) continue;
      ASSERT_LT(k, v.count[p]);
      EXPECT_EQ(v.neighbor[v.slot(p, k++)], p + lf.entries[size_t(st.first + q)].offset);
    }
    EXPECT_EQ(k, v.count[p]);
  }
}

TEST(LatticeFamilies, BodiesThatAreNotFullBoxGridsKeepExplicitFamilies) {
  auto none = [](const SimulationInput& in) {
    return lattice_families(in.particles, in.materials, bonds_of(in)).stencils.size();
  };
  EXPECT_EQ(none(lattice_block(10, 9, 8, 1e-3, 1e-3, 0.2)), 0u);  // jittered
  auto mixed = lattice_block(10, 9, 8, 1e-3);
  mixed.particles.volume[17] *= real(1.5);  // one particle of another volume
  EXPECT_EQ(none(mixed), 0u);
  const auto full = lattice_block(10, 9, 8, 1e-3);
  auto holed = full;  // the last particle missing: not a full box
  holed.particles = ParticleSet();
  for (size_t i = 0; i + 1 < full.particles.size(); ++i)
    holed.particles.add(full.particles.rest[i], {0, 0, 0}, full.particles.volume[i], full.particles.mass[i],
                        full.particles.strain_limit0[i], 0, 0);
  EXPECT_EQ(none(holed), 0u);
  EXPECT_EQ(none(lattice_block(6, 9, 8, 1e-3)), 0u);  // offsets along x would alias (6 <= 2 * 3)
  auto interleaved = lattice_block(10, 9, 8, 1e-3);   // two bodies taking turns
  for (size_t i = 0; i < interleaved.particles.size(); ++i) interleaved.particles.body[i] = int32_t(i % 2);
  EXPECT_EQ(none(interleaved), 0u);
}

TEST(LatticeFamilies, TwoBoxBodiesGetOneStencilEach) {
  auto in = lattice_block(10, 9, 8, 1e-3);
  const size_t half = in.particles.size();
  auto other = lattice_block(12, 10, 7, 1e-3);
  for (size_t i = 0; i < other.particles.size(); ++i)
    in.particles.add(other.particles.rest[i] + Vec3{real(0.05), 0, 0}, {0, 0, 0}, other.particles.volume[i],
                     other.particles.mass[i], other.particles.strain_limit0[i], 0, 1);
  const LatticeFamilies lf = lattice_families(in.particles, in.materials, bonds_of(in));
  ASSERT_EQ(lf.stencils.size(), 2u);
  EXPECT_EQ(lf.stencil[0], 0);
  EXPECT_EQ(lf.stencil[half], 1);
  EXPECT_EQ(lf.stencils[0].size, lf.stencils[1].size);
  EXPECT_EQ(lf.entries[size_t(lf.stencils[1].first + 1)].offset, 12 * (-1 + 10 * -3));
}

// Ranks as threads: all() and union_of() wait for every rank's contribution.
class ThreadReduce {
 public:
  explicit ThreadReduce(int ranks) : ranks_(ranks) {}
  struct Rank final : StencilReduce {
    ThreadReduce* shared;
    explicit Rank(ThreadReduce* s) : shared(s) {}
    bool all(bool mine) override {
      const std::vector<int32_t> r = shared->combine({mine ? 1 : 0});
      return std::count(r.begin(), r.end(), 0) == 0;
    }
    std::vector<int32_t> union_of(const std::vector<int32_t>& mine) override {
      std::vector<int32_t> r = shared->combine(mine);
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      return r;
    }
  };

 private:
  // Every rank's values together, once all ranks have given theirs.
  std::vector<int32_t> combine(const std::vector<int32_t>& mine) {
    std::unique_lock<std::mutex> lock(m_);
    const int64_t round = round_;
    pool_.insert(pool_.end(), mine.begin(), mine.end());
    if (++arrived_ == ranks_) {
      result_ = pool_;
      pool_.clear();
      arrived_ = 0;
      ++round_;
      cv_.notify_all();
    } else {
      cv_.wait(lock, [&] { return round_ != round; });
    }
    return result_;
  }
  int ranks_, arrived_ = 0;
  int64_t round_ = 0;
  std::vector<int32_t> pool_, result_;
  std::mutex m_;
  std::condition_variable cv_;
};

// A rank's families as the engine builds them: its own particles' (global[0, owned)) whole-run
// families, partners as local indices (global: local -> whole-run index).
BondLists local_bonds(const BondsView& wv, const std::vector<int32_t>& global, int32_t owned) {
  std::vector<int32_t> local_of(static_cast<size_t>(wv.n));
  for (size_t l = 0; l < global.size(); ++l) local_of[size_t(global[l])] = int32_t(l);
  BondLists b;
  b.count.assign(global.size(), 0);
  int32_t longest = 0;
  for (int32_t l = 0; l < owned; ++l) longest = std::max(longest, wv.count[global[size_t(l)]]);
  const int64_t slices = (int64_t(global.size()) + kSliceWidth - 1) / kSliceWidth;
  for (int64_t q = 0; q <= slices; ++q) b.slice_offset.push_back(q * int64_t(longest) * kSliceWidth);
  b.neighbor.assign(size_t(b.slice_offset.back()), 0);
  const BondsView lv = b.view();
  for (int32_t l = 0; l < owned; ++l) {
    const int32_t g = global[size_t(l)];
    b.count[size_t(l)] = wv.count[g];
    for (int32_t k = 0; k < wv.count[g]; ++k) {
      const int32_t nb = wv.neighbor[wv.slot(g, k)];
      const int32_t j = local_of[size_t(bond_partner(nb))];
      b.neighbor[size_t(lv.slot(l, k))] = bond_intact(nb) ? j : ~j;
    }
  }
  return b;
}

// Every rank's rank_lattice_families, the ranks as threads.
std::vector<LatticeFamilies> rank_parts(const SimulationInput& in, const std::vector<BondLists>& locals,
                                        const std::vector<std::vector<int32_t>>& globals,
                                        const std::vector<int32_t>& owned) {
  const int ranks = int(locals.size());
  ThreadReduce shared(ranks);
  std::vector<LatticeFamilies> parts(static_cast<size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      ThreadReduce::Rank reduce(&shared);
      parts[size_t(r)] = rank_lattice_families(in.particles, in.materials, locals[size_t(r)],
                                               globals[size_t(r)], owned[size_t(r)], reduce);
    });
  for (auto& t : threads) t.join();
  return parts;
}

TEST(LatticeFamilies, RanksBuildTheirPartsOfTheWholeRunsTables) {
  // Two box bodies; rank 0 owns the first 30 particles (a corner of the first body: alone, its
  // families use no offset below the first layer, so its stencil needs the other ranks'), rank 1
  // the rest of the first half, rank 2 the others; each in reverse order, then every other
  // particle after its own, so each of its partners has a local index.
  auto in = lattice_block(10, 9, 8, 1e-3);
  auto other = lattice_block(12, 10, 7, 1e-3);
  for (size_t i = 0; i < other.particles.size(); ++i)
    in.particles.add(other.particles.rest[i] + Vec3{real(0.05), 0, 0}, {0, 0, 0}, other.particles.volume[i],
                     other.particles.mass[i], other.particles.strain_limit0[i], 0, 1);
  const BondLists whole_bonds = bonds_of(in);
  const LatticeFamilies whole = lattice_families(in.particles, in.materials, whole_bonds);
  ASSERT_EQ(whole.stencils.size(), 2u);
  const int32_t n = int32_t(in.particles.size());
  const BondsView wv = whole_bonds.view();
  const int ranks = 3;
  const auto owner = [&](int32_t g) { return g < 30 ? 0 : g < n / 2 ? 1 : 2; };
  std::vector<std::vector<int32_t>> globals(ranks);
  std::vector<int32_t> owned(ranks, 0);
  std::vector<BondLists> locals(ranks);
  for (int r = 0; r < ranks; ++r) {
    std::vector<int32_t>& global = globals[size_t(r)];
    for (int32_t g = n - 1; g >= 0; --g)
      if (owner(g) == r) global.push_back(g);
    owned[size_t(r)] = int32_t(global.size());
    for (int32_t g = 0; g < n; ++g)
      if (owner(g) != r) global.push_back(g);
    locals[size_t(r)] = local_bonds(wv, global, owned[size_t(r)]);
  }
  const std::vector<LatticeFamilies> parts = rank_parts(in, locals, globals, owned);
  int64_t at_offsets = 0;
  for (int r = 0; r < ranks; ++r) {
    const LatticeFamilies& p = parts[size_t(r)];
    ASSERT_EQ(p.words, whole.words);
    const size_t held = p.stencil.size();
    const BondsView lv = locals[size_t(r)].view();
    for (int32_t l = 0; l < owned[size_t(r)]; ++l) {
      const int32_t g = globals[size_t(r)][size_t(l)];
      ASSERT_GE(p.stencil[size_t(l)], 0) << "rank " << r << " particle " << g;
      // The rank's stencil is the whole run's: its entries' geometry, and its offsets where it
      // is the listed one; the copy with local offsets finds every partner at them.
      const Stencil& st = p.stencils[size_t(p.stencil[size_t(l)])];
      const Stencil& wst = whole.stencils[size_t(whole.stencil[size_t(g)])];
      ASSERT_EQ(st.size, wst.size);
      EXPECT_EQ(wst.listed, 0);
      at_offsets += st.listed == 0;
      int32_t k = 0;
      for (int32_t q = 0; q < st.size; ++q) {
        const StencilEntry &e = p.entries[size_t(st.first + q)], &we = whole.entries[size_t(wst.first + q)];
        EXPECT_EQ(e.weight, we.weight);
        EXPECT_EQ(e.xi.w, we.xi.w);
        if (st.listed) {
          EXPECT_EQ(e.offset, we.offset);
        }
        if (!bit(p, p.present, l, q)) continue;
        const int32_t j = bond_partner(lv.neighbor[lv.slot(l, k++)]);
        if (!st.listed) {
          EXPECT_EQ(j, l + e.offset) << "rank " << r << " particle " << g << " entry " << q;
        }
      }
      for (int32_t w = 0; w < whole.words; ++w) {
        EXPECT_EQ(p.present[size_t(w) * held + size_t(l)], whole.present[size_t(w) * size_t(n) + size_t(g)]);
        EXPECT_EQ(p.intact[size_t(w) * held + size_t(l)], whole.intact[size_t(w) * size_t(n) + size_t(g)]);
      }
    }
  }
  // Ranks 1 and 2 hold whole layers in reverse order: their inner particles find their partners
  // at (negated) offsets of their own.
  EXPECT_GT(at_offsets, n / 4);
}

TEST(LatticeFamilies, RanksOfAPartitionReadPartnersAtLocalOffsetsAwayFromTheirBoundaries) {
  // A 40 x 24 x 8 block on 4 ranks as the partition lays them out (own particles interior first,
  // then boundary, each by global index; then the ghosts): the interior particles farther than a
  // horizon from their part's boundary read partners at local offsets, the others from lists.
  const SimulationInput in = lattice_block(40, 24, 8, 1e-3);
  const BondLists whole_bonds = bonds_of(in);
  const BondsView wv = whole_bonds.view();
  const int ranks = 4;
  const Partition partition = partition_particles(in.particles, in.materials, ranks);
  std::vector<BondLists> locals(ranks);
  std::vector<std::vector<int32_t>> globals(ranks);
  std::vector<int32_t> owned(ranks);
  for (int r = 0; r < ranks; ++r) {
    const RankLayout layout = rank_layout(partition, r);
    globals[size_t(r)] = layout.global;
    owned[size_t(r)] = layout.owned;
    locals[size_t(r)] = local_bonds(wv, layout.global, layout.owned);
  }
  const std::vector<LatticeFamilies> parts = rank_parts(in, locals, globals, owned);
  int64_t lattice = 0, listed = 0;
  for (int r = 0; r < ranks; ++r) {
    const LatticeFamilies& p = parts[size_t(r)];
    lattice += p.particles();
    listed += p.listed_particles();
    const BondsView lv = locals[size_t(r)].view();
    for (int32_t l = 0; l < owned[size_t(r)]; ++l) {
      const Stencil& st = p.stencils[size_t(p.stencil[size_t(l)])];
      if (st.listed) continue;
      int32_t k = 0;
      for (int32_t q = 0; q < st.size; ++q)
        if (bit(p, p.present, l, q)) {
          ASSERT_EQ(bond_partner(lv.neighbor[lv.slot(l, k++)]), l + p.entries[size_t(st.first + q)].offset)
              << "rank " << r << " particle " << l << " entry " << q;
        }
      ASSERT_EQ(k, lv.count[l]);
    }
  }
  EXPECT_EQ(lattice, int64_t(in.particles.size()));
  // Each part is 20 x 12 x 8 with two faces on other parts. Its interior is the 17 x 9 x 8
  // particles beyond a horizon (3 spacings) of those faces; of them, those whose partners are all
  // interior too, 14 x 6 x 8, read partners at offsets.
  EXPECT_EQ(lattice - listed, 4 * 14 * 6 * 8);
}

// The surface factors' rows: every lattice particle's row holds its bonds' factors by stencil
// entry (0 where its family lacks the entry), each distinct row is stored once, in the order of
// the first particle that has it.
TEST(LatticeFamilies, SurfaceRowsHoldEachParticlesFactorsOnce) {
  const SimulationInput in = lattice_block(14, 11, 9, 1e-3);
  const BondLists bonds = bonds_of(in);
  const LatticeFamilies lf = lattice_families(in.particles, in.materials, bonds);
  const BondsView v = bonds.view();
  // Factors that depend on the bond's direction and on how near the particle is to the low x
  // face, so that rows repeat along y and z and differ along x.
  std::vector<uint16_t> factor(bonds.neighbor.size(), 0);
  const int32_t n = int32_t(in.particles.size());
  for (int32_t i = 0; i < n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
      factor[size_t(v.slot(i, k))] = uint16_t(1000 + 7 * std::min(i % 14, 4) + (j - i + 4096) % 97);
    }
  const SurfaceRows rows = surface_rows(lf, bonds, factor);
  std::map<std::vector<uint16_t>, int32_t> seen;  // row -> its start
  int32_t next = 0;
  for (int32_t i = 0; i < n; ++i) {
    const Stencil& st = lf.stencils[size_t(lf.stencil[size_t(i)])];
    std::vector<uint16_t> row(size_t(st.size), 0);
    int32_t k = 0;
    for (int32_t q = 0; q < st.size; ++q)
      if (bit(lf, lf.present, i, q)) row[size_t(q)] = factor[size_t(v.slot(i, k++))];
    for (int32_t q = 0; q < st.size; ++q)
      ASSERT_EQ(rows.table[size_t(rows.row[size_t(i)] + q)], row[size_t(q)]);
    const auto [at, added] = seen.try_emplace(row, next);
    if (added) next += st.size;
    EXPECT_EQ(rows.row[size_t(i)], at->second) << "particle " << i;
  }
  EXPECT_EQ(rows.rows, int64_t(seen.size()));
  EXPECT_EQ(rows.table.size(), size_t(next));
  EXPECT_LT(rows.rows, n / 3);  // 8 classes along x, 7 along y and z: 392 rows
}

// Relative L2 difference of two vector fields.
double relative_l2(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double num = 0, den = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const Vec3 d = a[i] - b[i];
    num += double(dot(d, d));
    den += double(dot(b[i], b[i]));
  }
  return std::sqrt(num / den);
}

// Runs `in` with lattice and with explicit families and compares: the same bonds broken, and
// the motion as close as rounding leaves it (see kLambda: a few ulps per bond and step, grown
// over the run). A particle's net force is the small remainder of its ~178 bond forces, which
// cancel to ~1% of their sizes once it moves with its neighbours, so its relative difference
// is ~100x that of the bond forces.
void expect_same_run(SimulationInput in, int64_t steps) {
  auto lattice = make_cpu_engine(in);
  ASSERT_GT(lattice->family_stats().lattice_particles, 0);
  in.lattice_families = false;
  auto listed = make_cpu_engine(in);
  EXPECT_EQ(listed->family_stats().lattice_particles, 0);
  lattice->advance(steps);
  listed->advance(steps);
  ASSERT_GT(lattice->broken_bonds(), 0) << "the run must break bonds";
  EXPECT_EQ(lattice->broken_bonds(), listed->broken_bonds());
  ParticleState a, b;
  lattice->read_state(a);
  listed->read_state(b);
  EXPECT_LT(relative_l2(a.disp, b.disp), 1e-5);
  EXPECT_LT(relative_l2(a.vel, b.vel), 1e-4);
  EXPECT_LT(relative_l2(a.force, b.force), 1e-3);
  BondLists la, lb;
  lattice->read_bonds(la);
  listed->read_bonds(lb);
  int64_t differ = 0;
  for (size_t k = 0; k < la.neighbor.size(); ++k) differ += la.neighbor[k] != lb.neighbor[k];
  EXPECT_EQ(differ, 0);
}

SimulationInput pulled_apart(SimulationInput in, int nx, double v) {
  return testing::pulled_apart(std::move(in), nx, kLambda, v);
}

TEST(LatticeFamilies, BondBasedBreakingRunsAsWithExplicitFamilies) {
  const auto in = pulled_apart(lattice_block(16, 8, 8, kLambda, 2e-4), 16, 2);
  expect_same_run(in, 150);
}

TEST(LatticeFamilies, PlasticStateBasedRunsAsWithExplicitFamilies) {
  const auto in = pulled_apart(state_block(16, 8, 8, kLambda, 2e-4, true), 16, 2);
  expect_same_run(in, 150);
}

TEST(LatticeFamilies, CutAndWeakenedBondsKeepTheirSlots) {
  auto in = pulled_apart(lattice_block(16, 8, 8, kLambda, 4e-4), 16, 2);
  CutTriangle a, b;  // weaken the bonds across x = 8 lambda (by half), remove those across 4 lambda
  a.corner = {{{8 * kLambda, -1, -1}, {8 * kLambda, 1, -1}, {8 * kLambda, 1, 1}}};
  b.corner = {{{8 * kLambda, -1, -1}, {8 * kLambda, 1, 1}, {8 * kLambda, -1, 1}}};
  a.strength = b.strength = 0.5;
  CutTriangle c = a, d = b;
  for (auto* t : {&c, &d}) {
    for (auto& p : t->corner) p[0] = 4.25 * kLambda;
    t->strength = 0;
  }
  in.cuts = {a, b, c, d};
  auto e = make_cpu_engine(in);
  EXPECT_GT(e->family_stats().cuts.removed, 0);
  EXPECT_GT(e->family_stats().cuts.weakened, 0);
  // The weak bits are the weakened slots: only those read their strength.
  BondLists lists;
  e->read_bonds(lists);
  std::vector<uint8_t> strength;
  cut_bonds(in.cuts, in.particles.rest, in.particles.body, longest_bond_bound(in.particles, in.materials),
            lists,
            strength);  // lists already cut: weakens only
  LatticeFamilies lf = lattice_families(in.particles, in.materials, lists);
  mark_weak_lattice_bonds(lf, lists, strength);
  int64_t weak = 0;
  for (uint32_t w : lf.weak) weak += __builtin_popcount(w);
  EXPECT_EQ(weak, e->family_stats().cuts.weakened);
  expect_same_run(in, 150);
}

// `in` run for 2 half steps at once and, from a snapshot after the first half restored into a
// fresh engine, the second half again: both engines' states, the snapshot, and the bonds broken
// by then.
struct RestoredRun {
  std::unique_ptr<Engine> whole, resumed;
  EngineSnapshot snapshot;
  int64_t broken_at_snapshot = 0;
  ParticleState whole_state, resumed_state;
};

RestoredRun restored_run(const SimulationInput& in, int64_t half) {
  RestoredRun r;
  r.whole = make_cpu_engine(in);
  r.whole->advance(2 * half);
  auto first = make_cpu_engine(in);
  first->advance(half);
  first->save(r.snapshot);
  r.broken_at_snapshot = first->broken_bonds();
  r.resumed = make_cpu_engine(in);
  r.resumed->restore(r.snapshot);
  r.resumed->advance(half);
  r.whole->read_state(r.whole_state);
  r.resumed->read_state(r.resumed_state);
  return r;
}

TEST(LatticeFamilies, SnapshotsRestoreTheIntactBits) {
  const auto in = pulled_apart(lattice_block(16, 8, 8, kLambda, 2e-4), 16, 2);
  RestoredRun r = restored_run(in, 75);
  ASSERT_GT(r.broken_at_snapshot, 0);
  EXPECT_EQ(relative_l2(r.whole_state.disp, r.resumed_state.disp), 0.0);
  EXPECT_EQ(r.whole->broken_bonds(), r.resumed->broken_bonds());
  // A snapshot whose families list the bonds in another order is refused.
  std::swap(r.snapshot.neighbor[0], r.snapshot.neighbor[size_t(kSliceWidth)]);
  EXPECT_THROW(make_cpu_engine(in)->restore(r.snapshot), std::invalid_argument);
}

// A plastic run restored from a snapshot, whose mirror of the histories is derived from the
// histories alone (mirror_plastic), continues with the bits of the run that kept the mirror as
// `springforces` wrote it (each thread moving its partners' ends as their own threads move them,
// plasticity.h), with lattice and with explicit families; particles flowed before the snapshot.
TEST(LatticeFamilies, PlasticRunsRestoredFromTheirHistoryContinueTheSame) {
  for (bool lattice : {true, false}) {
    auto in = pulled_apart(state_block(16, 8, 8, kLambda, 4e-3, true), 16, 20);  // flows in the middle
    in.lattice_families = lattice;
    const RestoredRun r = restored_run(in, 75);
    EXPECT_EQ(r.whole->family_stats().lattice_particles > 0, lattice);
    const std::vector<real>& e = r.snapshot.plastic;
    const int64_t flowed = std::count_if(e.begin(), e.end(), [](real x) { return x != 0; });
    EXPECT_GT(flowed, int64_t(e.size() / 20)) << "bonds whose ends flowed";
    EXPECT_EQ(relative_l2(r.whole_state.disp, r.resumed_state.disp), 0.0) << lattice;
    EXPECT_EQ(relative_l2(r.whole_state.force, r.resumed_state.force), 0.0) << lattice;
    EXPECT_EQ(r.whole->broken_bonds(), r.resumed->broken_bonds());
  }
}

}  // namespace
}  // namespace pd
