// Contact ghosts of a partitioned run: whenever the contact lists are built, each rank receives
// the other ranks' particles that lie, at their current positions, within the contact reach of
// the box around its own (except those it already holds as bond ghosts), so fragments that fly
// across a rank boundary still collide. They are chosen and packed where the state lives, placed
// after the bond ghosts in ascending global index, and refreshed by the halo every step until
// the next build.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cuda/engine/engine_state.h"
#include "cuda/parallel/comm.h"
#include "cuda/parallel/halo.h"
#include "cuda/parallel/partition.h"

namespace pd {

// What a contact ghost needs to be hashed, listed and pushed.
struct GhostRecord {
  Vec4 rest;  // X, V
  Vec4 disp;
  Vec3 vel;
  int32_t global_id;
  int32_t body;
  uint16_t material;
  uint16_t pad;
};

// An axis-aligned box in double precision. `+` is the union and the default (empty) box its
// identity, so a backend's sum reduction gives the box around a set of points (exactly, in any
// order).
struct GhostBox {
  double lo[3] = {1e300, 1e300, 1e300};
  double hi[3] = {-1e300, -1e300, -1e300};

  PD_HD GhostBox operator+(const GhostBox& o) const {
    GhostBox u;
    for (int a = 0; a < 3; ++a) {
      u.lo[a] = lo[a] < o.lo[a] ? lo[a] : o.lo[a];
      u.hi[a] = hi[a] > o.hi[a] ? hi[a] : o.hi[a];
    }
    return u;
  }
};

// A particle's current position, X + u, in double precision.
PD_HD inline GhostBox point_box(const Vec4& x, const Vec4& u) {
  GhostBox b;
  b.lo[0] = b.hi[0] = double(x.x) + u.x;
  b.lo[1] = b.hi[1] = double(x.y) + u.y;
  b.lo[2] = b.hi[2] = double(x.z) + u.z;
  return b;
}

// The selection runs where the state lives (on the GPU of a CUDA rank): the box, each peer's test
// and the packing of the chosen particles' records are kernels, and only those records travel to
// the host, so a rebuild costs a few passes over the own particles instead of downloading them.
template <class Exec>
class ContactGhosts {
 public:
  ContactGhosts() = default;
  ContactGhosts(const RankLayout& layout, Comm& comm)
      : comm_(&comm), owned_(layout.owned), held_(int32_t(layout.global.size())), send_(layout.send) {}

  // Replaces the contact ghosts in `state` (after its own particles and bond ghosts) with those
  // within `reach` of this rank's own now, and gives the halo their lists. Returns the particles
  // the rank now holds.
  int32_t gather(DeviceMemory<Exec>& mem, EngineState<Exec>& state, Halo<Exec>& halo, double reach) {
    const int ranks = comm_->size();
    const size_t peers = static_cast<size_t>(ranks);
    Exec& exec = mem.exec();
    if (bond_ghost_of_.empty()) allocate(mem);
    const Vec4* rest = state.rest.data();
    const Vec4* disp = state.disp.data();

    // Every rank's box around its own particles' current positions.
    const GhostBox mine = exec.template reduce_sum<GhostBox>(
        "ghosts/box", owned_, [=] PD_HD(int64_t i) { return point_box(rest[i], disp[i]); });
    std::vector<double> box(mine.lo, mine.lo + 3);
    box.insert(box.end(), mine.hi, mine.hi + 3);
    std::vector<std::vector<char>> out(peers, to_bytes(box)), in(peers);
    for (int r = 0; r < ranks; ++r)
      in[size_t(r)].resize(r == comm_->rank() ? 0 : box.size() * sizeof(double));
    out[size_t(comm_->rank())].clear();
    comm_->exchange(out, in);

    // Own particles within reach of each peer's box that the peer does not hold already, in
    // ascending global index (the order the peer places them in).
    std::vector<std::vector<int32_t>> send(peers), recv(peers);
    std::vector<std::vector<GhostRecord>> records(peers);
    for (int s = 0; s < ranks; ++s) {
      if (s == comm_->rank()) continue;
      const std::vector<double> peer = from_bytes<double>(in[size_t(s)]);
      select(mem, state, peer, reach * 1.01, bond_ghost_of_[size_t(s)].data(), send[size_t(s)],
             records[size_t(s)]);
    }
    // Their counts, then the records.
    for (int s = 0; s < ranks; ++s) {
      out[size_t(s)] = s == comm_->rank()
                           ? std::vector<char>{}
                           : to_bytes(std::vector<int64_t>{int64_t(records[size_t(s)].size())});
      in[size_t(s)].assign(s == comm_->rank() ? 0 : sizeof(int64_t), 0);
    }
    comm_->exchange(out, in);
    for (int s = 0; s < ranks; ++s) {
      const int64_t count = s == comm_->rank() ? 0 : from_bytes<int64_t>(in[size_t(s)])[0];
      out[size_t(s)] = to_bytes(records[size_t(s)]);
      in[size_t(s)].assign(size_t(count) * sizeof(GhostRecord), 0);
    }
    comm_->exchange(out, in);

    // Placed after the bond ghosts in ascending global index.
    struct Arrival {
      GhostRecord r;
      int peer;
      size_t at;
    };
    std::vector<Arrival> arrivals;
    for (int s = 0; s < ranks; ++s) {
      const std::vector<GhostRecord> got = from_bytes<GhostRecord>(in[size_t(s)]);
      for (size_t k = 0; k < got.size(); ++k) arrivals.push_back({got[k], s, k});
    }
    std::sort(arrivals.begin(), arrivals.end(),
              [](const Arrival& a, const Arrival& b) { return a.r.global_id < b.r.global_id; });
    const int32_t total = held_ + int32_t(arrivals.size());
    if (size_t(total) > state.rest.size()) state.reserve_particles(mem, size_t(total) + size_t(total) / 4);
    state.n = total;
    std::vector<Vec4> g_rest, g_disp;
    std::vector<Vec3> g_vel;
    std::vector<int32_t> g_id, g_body;
    std::vector<uint16_t> g_material;
    for (size_t k = 0; k < arrivals.size(); ++k) {
      const GhostRecord& r = arrivals[k].r;
      g_rest.push_back(r.rest);
      g_disp.push_back(r.disp);
      g_vel.push_back(r.vel);
      g_id.push_back(r.global_id);
      g_body.push_back(r.body);
      g_material.push_back(r.material);
      recv[size_t(arrivals[k].peer)].push_back(held_ + int32_t(k));
    }
    place(exec, state.rest.data(), g_rest);
    place(exec, state.disp.data(), g_disp);
    place(exec, state.vel.data(), g_vel);
    place(exec, state.global_id.data(), g_id);
    place(exec, state.body.data(), g_body);
    place(exec, state.material.data(), g_material);
    halo.set_extra(send, recv);
    return total;
  }

  int32_t held() const { return held_; }

  // (Public only because nvcc takes no device lambda in a private member function.)
  // The own particles whose current position lies within `margin` of the box `peer` and that
  // the peer does not hold (`held`): their local indices into `send` and their records into
  // `records`, both in ascending global index.
  void select(DeviceMemory<Exec>& mem, EngineState<Exec>& state, const std::vector<double>& peer,
              double margin, const uint8_t* held, std::vector<int32_t>& send,
              std::vector<GhostRecord>& records) {
    Exec& exec = mem.exec();
    GhostBox near_box;
    for (int a = 0; a < 3; ++a) {
      near_box.lo[a] = peer[size_t(a)] - margin;
      near_box.hi[a] = peer[size_t(a + 3)] + margin;
    }
    const Vec4* rest = state.rest.data();
    const Vec4* disp = state.disp.data();
    const Vec3* vel = state.vel.data();
    const int32_t* global = state.global_id.data();
    const int32_t* body = state.body.data();
    const uint16_t* material = state.material.data();
    if (chosen_.size() == 0) {
      chosen_ = mem.template make<int64_t>(size_t(owned_));
      slot_ = mem.template make<int64_t>(size_t(owned_));
    }
    int64_t* chosen = chosen_.data();
    int64_t* slot = slot_.data();
    exec.parallel_for("ghosts/select", owned_, [=] PD_HD(int64_t i) {
      const GhostBox x = point_box(rest[i], disp[i]);
      bool near = !held[i];
      for (int a = 0; a < 3; ++a) near = near && x.lo[a] >= near_box.lo[a] && x.lo[a] <= near_box.hi[a];
      chosen[i] = near ? 1 : 0;
    });
    const int64_t count = exec.exclusive_scan(chosen, slot, owned_);
    send.clear();
    records.clear();
    if (count == 0) return;
    if (size_t(count) > picked_.size()) {
      mem.drop(picked_);
      mem.drop(packed_);
      picked_ = mem.template make<int32_t>(size_t(count));
      packed_ = mem.template make<GhostRecord>(size_t(count));
    }
    int32_t* picked = picked_.data();
    GhostRecord* packed = packed_.data();
    exec.parallel_for("ghosts/pack", owned_, [=] PD_HD(int64_t i) {
      if (!chosen[i]) return;
      const int64_t k = slot[i];
      picked[k] = int32_t(i);
      packed[k] = GhostRecord{rest[i], disp[i], vel[i], global[i], body[i], material[i], 0};
    });
    std::vector<int32_t> local(static_cast<size_t>(count));
    std::vector<GhostRecord> got(static_cast<size_t>(count));
    exec.download(local.data(), picked, local.size() * sizeof(int32_t));
    exec.download(got.data(), packed, got.size() * sizeof(GhostRecord));
    std::vector<size_t> order(got.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return got[a].global_id < got[b].global_id; });
    send.resize(order.size());
    records.resize(order.size());
    for (size_t k = 0; k < order.size(); ++k) {
      send[k] = local[order[k]];
      records[k] = got[order[k]];
    }
  }

 private:
  // Per peer, which own particles it holds as bond ghosts.
  void allocate(DeviceMemory<Exec>& mem) {
    for (const std::vector<int32_t>& list : send_) {
      std::vector<uint8_t> flags(size_t(owned_), 0);
      for (int32_t i : list) flags[size_t(i)] = 1;
      bond_ghost_of_.push_back(mem.make_from(flags));
    }
  }

  // Writes `values` at the contact ghosts' place of a state array.
  template <class T>
  void place(Exec& exec, T* array, const std::vector<T>& values) const {
    if (!values.empty()) exec.upload(array + held_, values.data(), values.size() * sizeof(T));
  }

  Comm* comm_ = nullptr;
  int32_t owned_ = 0, held_ = 0;            // own particles; own and bond ghosts
  std::vector<std::vector<int32_t>> send_;  // per peer, the own particles it holds as bond ghosts
  std::vector<DeviceArray<uint8_t, Exec>> bond_ghost_of_;  // the same as flags per own particle
  DeviceArray<int64_t, Exec> chosen_, slot_;               // per own particle: chosen, its place
  DeviceArray<int32_t, Exec> picked_;                      // the chosen's local indices
  DeviceArray<GhostRecord, Exec> packed_;                  // and their records
};

}  // namespace pd
