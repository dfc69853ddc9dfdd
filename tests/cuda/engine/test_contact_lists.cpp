// The contact lists' buffers (cuda/engine/contact_lists.h): a partitioned rank's particle count
// changes at almost every build (contact ghosts come and go), so the buffers are kept while they
// hold the particles and grown with room to spare; lists built into larger buffers, or after a
// list outgrew its room, hold exactly the pairs within reach.
#include "cuda/engine/contact_lists.h"

#include <gtest/gtest.h>

#include <vector>

#include "cuda/exec_cpu.h"
#include "tests/support/particle_arrays.h"

namespace pd {
namespace {

constexpr real kSpacing = real(0.01);

// n particles in twins 0.5 spacing apart (within the reach of two at rest, 0.9 spacing), the twins
// 3 spacings apart; the last `cluster` particles instead crowd within 0.4 spacing of one point.
testing::ParticleArrays cloud(int32_t n, int32_t cluster) {
  testing::ParticleArrays a;
  for (int32_t i = 0; i < n; ++i) {
    Vec4 x{real((i / 2) * 3 + (i % 2) * 0.5) * kSpacing, 0, 0, real(1e-6)};
    if (i >= n - cluster)
      x = {real(-10 + 0.3 * (i % 7) / 7) * kSpacing, real(0.3 * (i % 5) / 5) * kSpacing,
           real(0.3 * (i % 3) / 3) * kSpacing, real(1e-6)};
    a.rest.push_back(x);
    a.disp.push_back({0, 0, 0, 0});
    a.vel.push_back({0, 0, 0});
    a.material.push_back(0);
  }
  return a;
}

MaterialTable spacing_table() {
  MaterialTable mt;
  mt.count = 1;
  mt.m[0].contact_spacing = kSpacing;
  return mt;
}

// Particle i's list as built.
std::vector<int32_t> list_of(const ContactLists<CpuExec>& lists, CpuExec& exec, int32_t i) {
  const ContactView c = lists.view(exec, real(1e-7), 0.0);
  std::vector<int32_t> list;
  for (int32_t k = 0; k < c.count[i]; ++k) list.push_back(c.partner[c.slot(i, k)]);
  return list;
}

TEST(ContactLists, KeepTheirBuffersWhileTheParticleCountChangesWithinThem) {
  CpuExec exec(nullptr);
  DeviceMemory<CpuExec> mem(&exec);
  const MaterialTable mt = spacing_table();
  ContactLists<CpuExec> lists;
  lists.allocate(mem, 32000, mt);
  const size_t exact = mem.bytes();
  lists.size_lists(mem, 31000, kContactCapacity);  // fewer: the same buffers
  EXPECT_EQ(mem.bytes(), exact);
  lists.size_lists(mem, 33600, kContactCapacity);  // more: grown, with room for 1/16 more (35,700)
  const size_t grown = mem.bytes();
  EXPECT_GT(grown, exact);
  for (int32_t n : {32000, 35700, 20000, 34000}) lists.size_lists(mem, n, kContactCapacity);
  EXPECT_EQ(mem.bytes(), grown);
  lists.size_lists(mem, 35701, kContactCapacity);
  EXPECT_GT(mem.bytes(), grown);
}

TEST(ContactLists, BuildEveryPairWithinReachInBuffersLargerThanTheCount) {
  CpuExec exec(nullptr);
  DeviceMemory<CpuExec> mem(&exec);
  const MaterialTable mt = spacing_table();
  ContactLists<CpuExec> lists;
  lists.allocate(mem, 600, mt);
  lists.size_lists(mem, 700, kContactCapacity);  // buffers for 1,724 (at least 1,024 more)
  const size_t before = mem.bytes();
  // 500 particles in those buffers: room for 8 x 1,724 / 500 = 27 partners each. The last 40 are
  // in a cluster, whose lists (39 partners) outgrow that: the build doubles the room and builds
  // again.
  testing::ParticleArrays particles = cloud(500, 40);
  lists.size_lists(mem, 500, kContactCapacity);
  EXPECT_EQ(mem.bytes(), before);
  ASSERT_TRUE(lists.refresh(mem, particles.view(), mt, real(1e-7), 0.0));
  EXPECT_GT(mem.bytes(), before);
  for (int32_t i = 0; i < 460; ++i)
    EXPECT_EQ(list_of(lists, exec, i), std::vector<int32_t>{i ^ 1}) << "particle " << i;
  for (int32_t i = 460; i < 500; ++i) {
    std::vector<int32_t> others;
    for (int32_t j = 460; j < 500; ++j)
      if (j != i) others.push_back(j);
    EXPECT_EQ(list_of(lists, exec, i), others) << "particle " << i;
  }
}

// position_update names a particle that left its skin once, and the engine refreshes the lists
// after every position_update; named twice all the same, the mover is relisted once (pass 1's
// claim), so its new list and its new partners' hold each pair once.
TEST(ContactLists, RelistAMoverNamedTwiceOnce) {
  CpuExec exec(nullptr);
  DeviceMemory<CpuExec> mem(&exec);
  const MaterialTable mt = spacing_table();
  const real dt = real(1e-7);
  ContactLists<CpuExec> lists;
  lists.allocate(mem, 500, mt);
  testing::ParticleArrays particles = cloud(500, 0);
  ASSERT_TRUE(lists.refresh(mem, particles.view(), mt, dt, 0.0));
  // Particle 0 (at 0, its twin at 0.5) moves to 2.7 spacings: beside the next twins, at 3 and 3.5.
  particles.disp[0] = {real(2.7) * kSpacing, 0, 0, 0};
  const ContactView c = lists.view(exec, dt, 0.0);
  report_mover(0, c);
  report_mover(0, c);
  ASSERT_TRUE(lists.refresh(mem, particles.view(), mt, dt, 0.0));
  // Relisted, not built again: the twin it left still lists it (beyond reach, an exact zero).
  EXPECT_EQ(list_of(lists, exec, 1), std::vector<int32_t>{0});
  EXPECT_EQ(list_of(lists, exec, 0), (std::vector<int32_t>{2, 3}));
  EXPECT_EQ(list_of(lists, exec, 2), (std::vector<int32_t>{0, 3}));
  EXPECT_EQ(list_of(lists, exec, 3), (std::vector<int32_t>{0, 2}));
  EXPECT_EQ(list_of(lists, exec, 4), std::vector<int32_t>{5});
}

}  // namespace
}  // namespace pd
