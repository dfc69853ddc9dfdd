// Contact ghosts of a partitioned run: whenever the contact lists are built, each rank receives
// the other ranks' particles that lie, at their current positions, within the contact reach of
// the box around its own (except those it already holds as bond ghosts), so fragments that fly
// across a rank boundary still collide. They are placed after the bond ghosts, in ascending
// global index, and refreshed by the halo every step until the next build.
#pragma once

#include <algorithm>
#include <array>
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

template <class Exec>
class ContactGhosts {
 public:
  ContactGhosts() = default;
  // `local`: the rank's particles in layout order (own first).
  ContactGhosts(const RankLayout& layout, const ParticleSet& local, Comm& comm)
      : comm_(&comm), owned_(layout.owned), held_(int32_t(layout.global.size())), global_(layout.global) {
    rest_.resize(size_t(owned_));
    material_.assign(local.material.begin(), local.material.begin() + owned_);
    body_.assign(local.body.begin(), local.body.begin() + owned_);
    for (int32_t i = 0; i < owned_; ++i)
      rest_[size_t(i)] = with_w(local.rest[size_t(i)], local.volume[size_t(i)]);
    by_global_.resize(size_t(owned_));
    for (int32_t i = 0; i < owned_; ++i) by_global_[size_t(i)] = i;
    std::sort(by_global_.begin(), by_global_.end(),
              [&](int32_t a, int32_t b) { return global_[size_t(a)] < global_[size_t(b)]; });
    bond_ghost_of_.assign(layout.send.size(), std::vector<uint8_t>(size_t(owned_), 0));
    for (size_t s = 0; s < layout.send.size(); ++s)
      for (int32_t i : layout.send[s]) bond_ghost_of_[s][size_t(i)] = 1;
  }

  // Replaces the contact ghosts in `state` (after its own particles and bond ghosts) with those
  // within `reach` of this rank's own now, and gives the halo their lists. Returns the particles
  // the rank now holds.
  int32_t gather(DeviceMemory<Exec>& mem, EngineState<Exec>& state, Halo<Exec>& halo, double reach) {
    const int ranks = comm_->size();
    const size_t peers = static_cast<size_t>(ranks);
    std::vector<Vec4> disp(static_cast<size_t>(owned_));
    std::vector<Vec3> vel(static_cast<size_t>(owned_));
    Exec& exec = mem.exec();
    exec.download(disp.data(), state.disp.data(), disp.size() * sizeof(Vec4));
    exec.download(vel.data(), state.vel.data(), vel.size() * sizeof(Vec3));
    // Own particles' current positions, once for the box and every peer's test.
    std::vector<std::array<double, 3>> position(static_cast<size_t>(owned_));
    for (int32_t i = 0; i < owned_; ++i) {
      const Vec4 &x = rest_[size_t(i)], &u = disp[size_t(i)];
      position[size_t(i)] = {double(x.x) + u.x, double(x.y) + u.y, double(x.z) + u.z};
    }

    // Every rank's box around its own particles' current positions.
    std::vector<double> box = {1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
    for (int32_t i = 0; i < owned_; ++i) {
      const std::array<double, 3>& x = position[size_t(i)];
      for (int a = 0; a < 3; ++a) {
        box[size_t(a)] = std::min(box[size_t(a)], x[a]);
        box[size_t(a + 3)] = std::max(box[size_t(a + 3)], x[a]);
      }
    }
    std::vector<std::vector<char>> out(peers, to_bytes(box)), in(peers);
    for (int r = 0; r < ranks; ++r)
      in[size_t(r)].resize(r == comm_->rank() ? 0 : box.size() * sizeof(double));
    out[size_t(comm_->rank())].clear();
    comm_->exchange(out, in);

    // Own particles within reach of each peer's box that the peer does not hold already, in
    // ascending global index (the order the peer places them in).
    std::vector<std::vector<int32_t>> send(peers), recv(peers);
    std::vector<std::vector<GhostRecord>> records(peers);
    const double margin = reach * 1.01;
    for (int s = 0; s < ranks; ++s) {
      if (s == comm_->rank()) continue;
      const std::vector<double> peer = from_bytes<double>(in[size_t(s)]);
      for (const int32_t i : by_global_) {
        if (bond_ghost_of_[size_t(s)][size_t(i)]) continue;
        const std::array<double, 3>& x = position[size_t(i)];
        bool near = true;
        for (int a = 0; a < 3; ++a)
          near = near && x[a] >= peer[size_t(a)] - margin && x[a] <= peer[size_t(a + 3)] + margin;
        if (!near) continue;
        send[size_t(s)].push_back(i);
        records[size_t(s)].push_back({rest_[size_t(i)], disp[size_t(i)], vel[size_t(i)], global_[size_t(i)],
                                      body_[size_t(i)], material_[size_t(i)], 0});
      }
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

 private:
  // Writes `values` at the contact ghosts' place of a state array.
  template <class T>
  void place(Exec& exec, T* array, const std::vector<T>& values) const {
    if (!values.empty()) exec.upload(array + held_, values.data(), values.size() * sizeof(T));
  }

  Comm* comm_ = nullptr;
  int32_t owned_ = 0, held_ = 0;  // own particles; own and bond ghosts
  std::vector<int32_t> global_;
  std::vector<int32_t> by_global_;  // own particles' local indices in ascending global index
  std::vector<Vec4> rest_;
  std::vector<uint16_t> material_;
  std::vector<int32_t> body_;
  std::vector<std::vector<uint8_t>> bond_ghost_of_;  // per peer, per own particle
};

}  // namespace pd
