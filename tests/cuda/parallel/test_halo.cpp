// The halo exchange (cuda/parallel/halo.h) on CPU ranks: ranks as threads of this process over
// an in-memory Comm, several fields at once, split into start and finish with work between, and
// the contact ghosts' extra lists; and the environment options' messages.
#include "cuda/parallel/halo.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "cuda/exec_cpu.h"
#include "tests/support/thread_comm.h"

namespace pd {
namespace {

// A row of particles 1 apart, horizon 2.5: with 3 ranks each holds a third and its neighbours'
// nearest particles as ghosts.
struct Row {
  ParticleSet ps;
  MaterialTable mt;
  explicit Row(int n) {
    mt.count = 1;
    mt.m[0].horizon = real(2.5);
    mt.m[0].spacing = real(1);
    for (int i = 0; i < n; ++i) ps.add({real(i), 0, 0}, {0, 0, 0}, 1, 1, real(0.01), 0, 0);
  }
};

// The value of particle g's entries on its owner, in field f.
Vec4 owner_value(int32_t g, int f) {
  return {real(g), real(f), real(-g), real(1000 + g)};
}

TEST(Halo, GhostsReceiveTheirOwnersValuesOfEveryField) {
  const Row row(40);
  const int ranks = 3;
  const Partition p = partition_particles(row.ps, row.mt, ranks);
  Mailboxes mail;
  std::vector<std::string> failures(ranks);
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      try {
        ThreadComm comm(mail, r, ranks);
        const RankLayout l = rank_layout(p, r);
        CpuExec exec(nullptr);
        DeviceMemory<CpuExec> mem(&exec);
        Halo<CpuExec> halo(mem, l, comm, HaloOptions{});
        const size_t held = l.global.size();
        // Own entries hold the owner's values, ghosts a marker; two fields of different types.
        std::vector<Vec4> a(held, Vec4{-1, -1, -1, -1});
        std::vector<int32_t> b(held, -1);
        for (int32_t i = 0; i < l.owned; ++i) {
          a[size_t(i)] = owner_value(l.global[size_t(i)], 0);
          b[size_t(i)] = 7 * l.global[size_t(i)];
        }
        DeviceArray<Vec4, CpuExec> da = mem.make_from(a);
        DeviceArray<int32_t, CpuExec> db = mem.make_from(b);
        halo.start(da, db);
        // (work between start and finish: the interior part of a launch)
        EXPECT_EQ(halo.exchanges(), 1);
        halo.finish();
        da.download(a);
        db.download(b);
        for (size_t i = 0; i < held; ++i) {
          const int32_t g = l.global[i];
          EXPECT_EQ(a[i].x, owner_value(g, 0).x) << "rank " << r << " local " << i;
          EXPECT_EQ(a[i].w, owner_value(g, 0).w) << "rank " << r << " local " << i;
          EXPECT_EQ(b[i], 7 * g) << "rank " << r << " local " << i;
        }
        // Bytes sent: per particle sent, one of each field.
        int64_t sent = 0;
        for (const auto& s : l.send) sent += int64_t(s.size());
        EXPECT_EQ(halo.bytes_sent(), sent * int64_t(sizeof(Vec4) + sizeof(int32_t)));
        EXPECT_STREQ(halo.transport(), "mpi");
      } catch (const std::exception& e) {
        failures[size_t(r)] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (int r = 0; r < ranks; ++r) EXPECT_EQ(failures[size_t(r)], "") << "rank " << r;
}

TEST(Halo, ExtraListsCarryContactGhostsAfterTheBondGhosts) {
  // Two ranks; rank 0 also sends its particle 0 (far from rank 1) to rank 1 as a contact ghost,
  // placed after rank 1's bond ghosts.
  const Row row(20);
  const Partition p = partition_particles(row.ps, row.mt, 2);
  Mailboxes mail;
  std::vector<std::string> failures(2);
  std::vector<std::thread> threads;
  for (int r = 0; r < 2; ++r)
    threads.emplace_back([&, r] {
      try {
        ThreadComm comm(mail, r, 2);
        const RankLayout l = rank_layout(p, r);
        CpuExec exec(nullptr);
        DeviceMemory<CpuExec> mem(&exec);
        Halo<CpuExec> halo(mem, l, comm, HaloOptions{});
        const int32_t first_global_of_rank0 = p.owned[0].front();
        std::vector<std::vector<int32_t>> send(2), recv(2);
        std::vector<int32_t> global = l.global;
        if (r == 0) {
          for (int32_t i = 0; i < l.owned; ++i)
            if (l.global[size_t(i)] == first_global_of_rank0) send[1].push_back(i);
        } else {
          recv[0].push_back(int32_t(l.global.size()));
          global.push_back(first_global_of_rank0);
        }
        halo.set_extra(send, recv);
        std::vector<int32_t> v(global.size(), -1);
        for (int32_t i = 0; i < l.owned; ++i) v[size_t(i)] = 3 * global[size_t(i)];
        DeviceArray<int32_t, CpuExec> dv = mem.make_from(v);
        halo.exchange(dv);
        dv.download(v);
        for (size_t i = 0; i < global.size(); ++i)
          EXPECT_EQ(v[i], 3 * global[i]) << "rank " << r << " local " << i;
      } catch (const std::exception& e) {
        failures[size_t(r)] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (int r = 0; r < 2; ++r) EXPECT_EQ(failures[size_t(r)], "") << "rank " << r;
}

TEST(Halo, EnvironmentOptionsAreCheckedWithTheAllowedValues) {
  setenv("PERIFRAC_HALO", "host", 1);
  setenv("PERIFRAC_HALO_OVERLAP", "0", 1);
  HaloOptions o = halo_options_from_env();
  EXPECT_EQ(o.transport, HaloOptions::Transport::kHost);
  EXPECT_EQ(o.overlap, 0);
  setenv("PERIFRAC_HALO", "infiniband", 1);
  try {
    halo_options_from_env();
    ADD_FAILURE() << "accepted PERIFRAC_HALO=infiniband";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("PERIFRAC_HALO='infiniband': allowed are auto, host and nccl"),
              std::string::npos)
        << e.what();
  }
  setenv("PERIFRAC_HALO", "auto", 1);
  setenv("PERIFRAC_HALO_OVERLAP", "yes", 1);
  EXPECT_THROW(halo_options_from_env(), std::runtime_error);
  unsetenv("PERIFRAC_HALO");
  unsetenv("PERIFRAC_HALO_OVERLAP");
  o = halo_options_from_env();
  EXPECT_EQ(o.transport, HaloOptions::Transport::kAuto);
  EXPECT_EQ(o.overlap, -1);
}

}  // namespace
}  // namespace pd
