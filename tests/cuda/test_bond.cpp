// Bond loops (cuda/kernels/bond.h): the listed family's three walks (ListedWalk) visit the same
// bonds with the same geometry, break the same ones and count the same bonds left intact.
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

}  // namespace
}  // namespace pd
