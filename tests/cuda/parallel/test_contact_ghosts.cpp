// The contact ghosts of a partitioned run (cuda/parallel/contact_ghosts.h) on two CPU ranks as
// threads: which particles a rank receives after some have flown across the boundary, in which
// order and with which values, and that the halo keeps them fresh afterwards.
#include "cuda/parallel/contact_ghosts.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>

#include "cuda/exec_cpu.h"
#include "tests/support/thread_comm.h"

namespace pd {
namespace {

// Eight particles on the x axis at x = global index. Rank 0 owns 0-3 and holds 4 as a bond
// ghost; rank 1 owns 4, 5, 7, 6 (in that local order) and holds 3. Particles 6 and 7 have flown
// to x = 2.5 and 3.5, into rank 0's reach; with that, rank 1's box reaches down to 2.5.
RankLayout layout_of(int rank) {
  RankLayout l;
  l.rank = rank;
  l.owned = 4;
  l.global = rank == 0 ? std::vector<int32_t>{0, 1, 2, 3, 4} : std::vector<int32_t>{4, 5, 7, 6, 3};
  l.send = {{}, {}};
  l.recv = {{}, {}};
  l.send[size_t(1 - rank)] = {rank == 0 ? 3 : 0};
  l.recv[size_t(1 - rank)] = {4};
  return l;
}

real displacement_of(int32_t global) {
  return global == 6 ? real(2.5 - 6) : global == 7 ? real(3.5 - 7) : real(0);
}

constexpr double kReach = 1.2;

// One rank's state as the engine holds it: rest (X, volume), displacement, velocity and the ids.
EngineState<CpuExec> state_of(DeviceMemory<CpuExec>& mem, const RankLayout& l) {
  EngineState<CpuExec> state;
  const size_t held = l.global.size();
  std::vector<Vec4> rest(held), disp(held);
  std::vector<Vec3> vel(held);
  std::vector<int32_t> body(held);
  std::vector<uint16_t> material(held);
  for (size_t i = 0; i < held; ++i) {
    const int32_t g = l.global[i];
    rest[i] = {real(g), 0, 0, real(0.5)};
    disp[i] = {displacement_of(g), 0, 0, real(0.01)};
    vel[i] = {real(g), real(-g), 0};
    body[i] = 100 + g;
    material[i] = uint16_t(g % 2);
  }
  state.rest = mem.make_from(rest);
  state.disp = mem.make_from(disp);
  state.vel = mem.make_from(vel);
  state.global_id = mem.make_from(l.global);
  state.body = mem.make_from(body);
  state.material = mem.make_from(material);
  state.n = int32_t(held);
  return state;
}

struct RankResult {
  std::string failure;
  std::vector<int32_t> global;  // the held particles' global ids after the gather
  std::vector<Vec4> disp;       // their displacements after one halo exchange
  std::vector<Vec3> vel;
  std::vector<int32_t> body;
};

TEST(ContactGhosts, RanksReceiveTheParticlesThatFlewIntoReachInGlobalOrder) {
  Mailboxes mail;
  RankResult result[2];
  std::vector<std::thread> threads;
  for (int r = 0; r < 2; ++r)
    threads.emplace_back([&, r] {
      try {
        ThreadComm comm(mail, r, 2);
        const RankLayout l = layout_of(r);
        CpuExec exec(nullptr);
        DeviceMemory<CpuExec> mem(&exec);
        Halo<CpuExec> halo(mem, l, comm, HaloOptions{});
        EngineState<CpuExec> state = state_of(mem, l);
        ContactGhosts<CpuExec> ghosts(l, comm);
        const int32_t total = ghosts.gather(mem, state, halo, kReach);
        EXPECT_EQ(total, state.n);
        // The owners move their particles on (y = 10 x global id); one exchange brings every
        // ghost, bond and contact, up to date.
        std::vector<Vec4> disp(static_cast<size_t>(total));
        exec.download(disp.data(), state.disp.data(), disp.size() * sizeof(Vec4));
        for (int32_t i = 0; i < l.owned; ++i) disp[size_t(i)].y = real(10 * l.global[size_t(i)]);
        exec.upload(state.disp.data(), disp.data(), disp.size() * sizeof(Vec4));
        halo.exchange(state.disp);
        RankResult& out = result[r];
        out.global.resize(size_t(total));
        out.disp.resize(size_t(total));
        out.vel.resize(size_t(total));
        out.body.resize(size_t(total));
        exec.download(out.global.data(), state.global_id.data(), size_t(total) * sizeof(int32_t));
        exec.download(out.disp.data(), state.disp.data(), size_t(total) * sizeof(Vec4));
        exec.download(out.vel.data(), state.vel.data(), size_t(total) * sizeof(Vec3));
        exec.download(out.body.data(), state.body.data(), size_t(total) * sizeof(int32_t));
      } catch (const std::exception& e) {
        result[r].failure = e.what();
      }
    });
  for (auto& t : threads) t.join();
  ASSERT_EQ(result[0].failure, "");
  ASSERT_EQ(result[1].failure, "");

  // Rank 0: its own, its bond ghost 4, then 6 and 7 (flown into reach) in ascending global index
  // though their owner holds them the other way round; 5 stays out of reach.
  EXPECT_EQ(result[0].global, (std::vector<int32_t>{0, 1, 2, 3, 4, 6, 7}));
  // Rank 1: particle 2 of rank 0; 3 is its bond ghost already, 1 out of reach.
  EXPECT_EQ(result[1].global, (std::vector<int32_t>{4, 5, 7, 6, 3, 2}));
  for (const RankResult& r : result)
    for (size_t i = 0; i < r.global.size(); ++i) {
      const int32_t g = r.global[i];
      EXPECT_EQ(r.disp[i].x, displacement_of(g)) << "global " << g;
      EXPECT_EQ(r.disp[i].y, real(10 * g)) << "global " << g;
      EXPECT_EQ(r.vel[i].y, real(-g)) << "global " << g;
      EXPECT_EQ(r.body[i], 100 + g) << "global " << g;
    }
}

// The selection alone: own particles near a peer's box, less those the peer holds, with their
// records, in ascending global index.
TEST(ContactGhosts, SelectionSkipsThePeersBondGhostsAndSortsByGlobalIndex) {
  Mailboxes mail;
  ThreadComm comm(mail, 1, 2);
  const RankLayout l = layout_of(1);
  CpuExec exec(nullptr);
  DeviceMemory<CpuExec> mem(&exec);
  EngineState<CpuExec> state = state_of(mem, l);
  ContactGhosts<CpuExec> ghosts(l, comm);
  const std::vector<double> peer_box = {0, 0, 0, 3, 0, 0};
  const DeviceArray<uint8_t, CpuExec> held = mem.make_from(std::vector<uint8_t>{1, 0, 0, 0});
  std::vector<int32_t> send;
  std::vector<GhostRecord> records;
  ghosts.select(mem, state, peer_box, kReach, held.data(), send, records);
  EXPECT_EQ(send, (std::vector<int32_t>{3, 2}));  // local 3 is global 6, local 2 global 7
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].global_id, 6);
  EXPECT_EQ(records[1].global_id, 7);
  EXPECT_EQ(records[0].rest.w, real(0.5));
  EXPECT_EQ(records[0].vel.x, 6);
  EXPECT_EQ(records[1].body, 107);
  EXPECT_EQ(records[1].material, 1);
  // A reach that does not cover 3.5 (3 + 0.4) leaves 7 out; 4 (held) stays out with any reach.
  ghosts.select(mem, state, peer_box, 0.4, held.data(), send, records);
  EXPECT_EQ(send, (std::vector<int32_t>{3}));
  ghosts.select(mem, state, peer_box, 100, held.data(), send, records);
  EXPECT_EQ(send, (std::vector<int32_t>{1, 3, 2}));
}

}  // namespace
}  // namespace pd
