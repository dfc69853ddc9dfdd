// Domain decomposition (cuda/parallel/partition.h): ownership, ghosts that hold every bond
// partner, and send and receive lists that pair up across ranks.
#include "cuda/parallel/partition.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>

namespace pd {
namespace {

constexpr double kLambda = 0.01;

// A block of nx x ny x nz particles at spacing lambda, horizon 3 lambda, partial volumes on.
struct Block {
  ParticleSet ps;
  MaterialTable mt;
  Block(int nx, int ny, int nz) {
    mt.count = 1;
    mt.m[0].horizon = real(3 * kLambda);
    mt.m[0].spacing = real(kLambda);
    const real v = real(kLambda * kLambda * kLambda);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x)
          ps.add({real(x * kLambda), real(y * kLambda), real(z * kLambda)}, {0, 0, 0}, v, v * 1000,
                 real(0.01), 0, 0);
  }
};

TEST(Partition, EveryParticleHasOneOwnerAndRanksAreBalanced) {
  const Block b(24, 10, 6);
  for (int ranks : {1, 2, 3, 5, 8}) {
    const Partition p = partition_particles(b.ps, b.mt, ranks);
    std::vector<int> seen(b.ps.size(), 0);
    for (int r = 0; r < ranks; ++r) {
      // Interior, then boundary, each ascending.
      const auto& own = p.owned[size_t(r)];
      ASSERT_LE(p.interior[size_t(r)], int32_t(own.size()));
      EXPECT_TRUE(std::is_sorted(own.begin(), own.begin() + p.interior[size_t(r)]));
      EXPECT_TRUE(std::is_sorted(own.begin() + p.interior[size_t(r)], own.end()));
      for (int32_t i : p.owned[size_t(r)]) {
        ++seen[size_t(i)];
        EXPECT_EQ(p.owner[size_t(i)], r);
      }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));
    // Equal expected bonds per particle here: the counts split as evenly as a bisection can.
    EXPECT_LT(partition_balance(p, b.ps, b.mt).imbalance, 1.02) << ranks << " ranks";
  }
}

TEST(Partition, GhostsHoldEveryPartnerWithinTheFamilyRadius) {
  const Block b(20, 8, 5);
  const Partition p = partition_particles(b.ps, b.mt, 4);
  const double radius = double(b.mt.m[0].family_radius()) * (1 + 1e-6);
  for (int r = 0; r < 4; ++r) {
    const RankLayout l = rank_layout(p, r);
    std::vector<char> held(b.ps.size(), 0);
    for (int32_t g : l.global) held[size_t(g)] = 1;
    for (int32_t i : p.owned[size_t(r)])
      for (size_t j = 0; j < b.ps.size(); ++j) {
        const Vec3 d = b.ps.rest[j] - b.ps.rest[size_t(i)];
        if (double(length(d)) <= radius) {
          EXPECT_TRUE(held[j]) << "rank " << r << " lacks partner " << j << " of " << i;
        }
      }
    // Own particles first (interior, then boundary), then ghosts, each part ascending.
    EXPECT_TRUE(std::is_sorted(l.global.begin(), l.global.begin() + l.interior));
    EXPECT_TRUE(std::is_sorted(l.global.begin() + l.interior, l.global.begin() + l.owned));
    EXPECT_TRUE(std::is_sorted(l.global.begin() + l.owned, l.global.end()));
  }
}

TEST(Partition, InteriorParticlesHaveEveryPartnerOnTheirOwnRank) {
  const Block b(24, 8, 6);
  const Partition p = partition_particles(b.ps, b.mt, 3);
  const double radius = double(b.mt.m[0].family_radius()) * (1 + 1e-6);
  for (int r = 0; r < 3; ++r) {
    const RankLayout l = rank_layout(p, r);
    // Each rank's slab is wider than two family radii here: it has interior and boundary particles.
    EXPECT_GT(l.interior, 0);
    EXPECT_LT(l.interior, l.owned);
    for (int32_t k = 0; k < l.owned; ++k) {
      const int32_t i = l.global[size_t(k)];
      bool reads_ghost = false;
      for (size_t j = 0; j < b.ps.size(); ++j)
        reads_ghost =
            reads_ghost || (p.owner[j] != r && double(length(b.ps.rest[j] - b.ps.rest[size_t(i)])) <= radius);
      if (k < l.interior) {
        EXPECT_FALSE(reads_ghost) << "interior particle " << i << " of rank " << r
                                  << " has a partner elsewhere";
      }
    }
    // Every boundary particle is sent to some rank.
    std::vector<char> sent(size_t(l.owned), 0);
    for (const auto& list : l.send)
      for (int32_t k : list) sent[size_t(k)] = 1;
    for (int32_t k = 0; k < l.owned; ++k) EXPECT_EQ(sent[size_t(k)] != 0, k >= l.interior) << k;
  }
}

TEST(Partition, SendAndReceiveListsPairUpAcrossRanks) {
  const Block b(16, 12, 4);
  const int ranks = 3;
  const Partition p = partition_particles(b.ps, b.mt, ranks);
  std::vector<RankLayout> layouts;
  for (int r = 0; r < ranks; ++r) layouts.push_back(rank_layout(p, r));
  for (int r = 0; r < ranks; ++r)
    for (int s = 0; s < ranks; ++s) {
      if (r == s) continue;
      const RankLayout &from = layouts[size_t(r)], &to = layouts[size_t(s)];
      ASSERT_EQ(from.send[size_t(s)].size(), to.recv[size_t(r)].size());
      for (size_t k = 0; k < from.send[size_t(s)].size(); ++k) {
        EXPECT_LT(from.send[size_t(s)][k], from.owned);
        EXPECT_GE(to.recv[size_t(r)][k], to.owned);
        EXPECT_EQ(from.global[size_t(from.send[size_t(s)][k])], to.global[size_t(to.recv[size_t(r)][k])]);
      }
    }
  // The local particle set follows the layout.
  const ParticleSet local = local_particles(b.ps, layouts[1]);
  ASSERT_EQ(local.size(), layouts[1].global.size());
  for (size_t k = 0; k < local.size(); ++k)
    EXPECT_EQ(local.rest[k].x, b.ps.rest[size_t(layouts[1].global[k])].x);
}

// Every rank computes the partition alone, with whatever threads it has: the result must not
// depend on them. Volumes varied so that the bisection's weights differ from particle to particle.
TEST(Partition, IsTheSameOnAnyNumberOfThreads) {
  Block b(30, 14, 9);
  for (size_t i = 0; i < b.ps.size(); ++i) b.ps.volume[i] *= real(1 + 0.5 * double(i % 7) / 7);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Partition one = partition_particles(b.ps, b.mt, 5);
  omp_set_num_threads(4);
  const Partition four = partition_particles(b.ps, b.mt, 5);
  omp_set_num_threads(threads);
  EXPECT_EQ(one.owner, four.owner);
  EXPECT_EQ(one.owned, four.owned);
  EXPECT_EQ(one.ghosts, four.ghosts);
  EXPECT_EQ(one.interior, four.interior);
}

// Where particles expect different numbers of bonds (half the block at twice the volume), the
// ranks split the expected bonds, not the particles.
TEST(Partition, SplitsTheExpectedBondsWhereParticlesDiffer) {
  Block b(40, 10, 6);
  for (size_t i = 0; i < b.ps.size(); ++i)
    if (b.ps.rest[i].x < real(20 * kLambda)) b.ps.volume[i] *= 2;
  for (int ranks : {2, 3, 4, 7}) {
    const Partition p = partition_particles(b.ps, b.mt, ranks);
    const PartitionBalance balance = partition_balance(p, b.ps, b.mt);
    EXPECT_LT(balance.imbalance, 1.03) << ranks << " ranks";
    if (ranks == 2) {  // the light half's rank holds more particles
      EXPECT_NE(balance.particles[0], balance.particles[1]);
    }
  }
}

// A mesh's sliver tets (volumes down to 1e-16 of the median) neither overflow the bisection's
// fixed-point weights nor pull the split towards themselves: they count as particles of an eighth
// of a cell, and the ranks still split the block evenly.
TEST(Partition, SliverParticlesCountAsAnEighthOfACell) {
  Block b(40, 10, 6);
  for (size_t i = 0; i < b.ps.size(); i += 97) b.ps.volume[i] *= real(1e-20);
  for (int ranks : {2, 3, 4}) {
    const Partition p = partition_particles(b.ps, b.mt, ranks);
    const PartitionBalance balance = partition_balance(p, b.ps, b.mt);
    EXPECT_LT(balance.imbalance, 1.03) << ranks << " ranks";
    for (int r = 0; r < ranks; ++r)
      EXPECT_NEAR(double(balance.particles[size_t(r)]), double(b.ps.size()) / ranks,
                  0.05 * double(b.ps.size()) / ranks)
          << ranks << " ranks, rank " << r;
  }
}

// Split on the families' sizes (the second split of a run whose estimate was off): each rank
// holds an even share of bonds plus particles, wherever the families are long or short.
TEST(Partition, FamilySizesSplitAsEvenlyAsTheBisectionCan) {
  const Block b(40, 10, 6);
  std::vector<int32_t> bonds(b.ps.size());
  for (size_t i = 0; i < bonds.size(); ++i) bonds[i] = b.ps.rest[i].x < real(10 * kLambda) ? 300 : 20;
  for (int ranks : {2, 3, 4}) {
    const Partition p = partition_particles(b.ps, b.mt, ranks, bonds);
    std::vector<double> share(size_t(ranks), 0);
    double total = 0;
    for (int r = 0; r < ranks; ++r)
      for (int32_t i : p.owned[size_t(r)]) share[size_t(r)] += bonds[size_t(i)] + 1;
    for (double s : share) total += s;
    // The cut falls between two particles (ordered along x, ties by index): off by at most a
    // particle's weight (301) per level of the bisection.
    for (int r = 0; r < ranks; ++r)
      EXPECT_NEAR(share[size_t(r)], total / ranks, 3 * 301.0) << ranks << " ranks, rank " << r;
    // The long families' end is split finer: rank 0 holds fewer particles than the last rank.
    EXPECT_LT(p.owned[0].size(), p.owned[size_t(ranks - 1)].size()) << ranks << " ranks";
  }
}

}  // namespace
}  // namespace pd
