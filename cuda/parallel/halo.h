// The halo exchange of a partitioned run: each rank sends its own particles' values of some
// fields to the ranks that hold them as ghosts, and receives its ghosts' values from their
// owners. Packed and unpacked by kernels on the backend, one message per field and peer, and
// split in two (start, finish) so that the interior particles' forces are computed while it
// travels:
// - CPU ranks: MPI straight from the packed buffers;
// - GPU ranks with a device link (NCCL, cuda/parallel/device_link.h): packing, the messages and
//   unpacking are queued on a second stream, which the boundary particles' kernels wait for; the
//   host waits for nothing;
// - GPU ranks without one: staged through host memory over MPI, the interior kernels running
//   while the messages travel.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/engine/device_memory.h"
#include "cuda/parallel/comm.h"
#include "cuda/parallel/device_link.h"
#include "cuda/parallel/partition.h"

namespace pd {

// How the halo travels, from the environment (for measurements; the defaults are the fast ones):
// PERIFRAC_HALO = auto (device to device where the build has NCCL and every rank of a host has
// a GPU of its own, else host memory) | host | nccl; PERIFRAC_HALO_OVERLAP = auto (overlapped
// unless NCCL carries it: over NVLink the exchange takes tens of microseconds, less than
// splitting the force kernels costs) | 1 (the interior forces while the halo travels) | 0 (the
// halo first). Measured in bench/results/mpi-scaling-4xH200-2026-11-26.txt.
struct HaloOptions {
  enum class Transport { kAuto, kHost, kNccl };
  Transport transport = Transport::kAuto;
  int overlap = -1;  // -1 auto, 0 or 1
};

inline HaloOptions halo_options_from_env() {
  HaloOptions o;
  if (const char* v = std::getenv("PERIFRAC_HALO")) {
    const std::string s = v;
    if (s == "auto")
      o.transport = HaloOptions::Transport::kAuto;
    else if (s == "host")
      o.transport = HaloOptions::Transport::kHost;
    else if (s == "nccl")
      o.transport = HaloOptions::Transport::kNccl;
    else
      throw std::runtime_error("environment PERIFRAC_HALO='" + s + "': allowed are auto, host and nccl");
  }
  if (const char* v = std::getenv("PERIFRAC_HALO_OVERLAP")) {
    const std::string s = v;
    if (s != "auto" && s != "0" && s != "1")
      throw std::runtime_error("environment PERIFRAC_HALO_OVERLAP='" + s + "': allowed are auto, 0 and 1");
    o.overlap = s == "auto" ? -1 : s == "1" ? 1 : 0;
  }
  return o;
}

template <class Exec>
class Halo {
 public:
  Halo() = default;
  Halo(DeviceMemory<Exec>& mem, const RankLayout& layout, Comm& comm, const HaloOptions& options)
      : exec_(&mem.exec()), mem_(&mem), comm_(&comm), base_send_(layout.send), base_recv_(layout.recv) {
    if constexpr (Exec::kDevice) {
      // Every rank decides alike (the link is made by all ranks together or by none); a device
      // link needs a GPU of its own for every rank of a host.
      const bool own_gpu = comm.min(comm.local_size() <= exec_->device_count() ? 1.0 : 0.0) > 0;
      const bool wanted = options.transport != HaloOptions::Transport::kHost;
      if (options.transport == HaloOptions::Transport::kNccl && !(device_link_available() && own_gpu))
        throw std::runtime_error(std::string("PERIFRAC_HALO=nccl: ") +
                                 (device_link_available()
                                      ? "NCCL needs a GPU of its own for every rank of a host"
                                      : "this build has no NCCL"));
      if (wanted && device_link_available() && own_gpu) link_ = make_device_link(comm);
    }
    set_extra(std::vector<std::vector<int32_t>>(base_send_.size()),
              std::vector<std::vector<int32_t>>(base_recv_.size()));
  }

  // Per peer, more particles sent and received after the bond ghosts' (contact ghosts,
  // cuda/parallel/contact_ghosts.h), replacing the last ones given.
  void set_extra(const std::vector<std::vector<int32_t>>& send,
                 const std::vector<std::vector<int32_t>>& recv) {
    std::vector<int32_t> all_send, all_recv;
    concatenate(base_send_, send, all_send, send_first_);
    concatenate(base_recv_, recv, all_recv, recv_first_);
    mem_->drop(send_index_);
    mem_->drop(recv_index_);
    send_index_ = mem_->make_from(all_send);
    recv_index_ = mem_->make_from(all_recv);
  }

  bool active() const { return comm_ != nullptr; }
  bool device_link() const { return link_ != nullptr; }
  // "nccl", "mpi via host memory" or "mpi".
  const char* transport() const { return link_ ? "nccl" : Exec::kDevice ? "mpi via host memory" : "mpi"; }
  int64_t bytes_sent() const { return bytes_sent_; }
  int64_t exchanges() const { return exchanges_; }
  // The exchanges' own time: with a device link, the second stream's (packing, messages,
  // unpacking; hidden where the interior forces took longer), up to the engine's last flush;
  // otherwise the host's time in start and finish (what the interior forces did not hide).
  double seconds() const {
    if constexpr (Exec::kDevice)
      if (link_) return exec_->side_seconds();
    return seconds_;
  }

  // Starts replacing every ghost's entries of `fields` by their owners'; finish() completes it.
  template <class... T>
  void start(DeviceArray<T, Exec>&... fields) {
    const auto t0 = std::chrono::steady_clock::now();
    constexpr size_t kFields = sizeof...(T);
    const std::array<size_t, kFields> size = {sizeof(T)...};
    const int64_t sends = int64_t(send_index_.size()), recvs = int64_t(recv_index_.size());
    // Field q's values at byte send_at[q] (recv_at[q]) of the buffers, each region 16-aligned.
    std::array<int64_t, kFields + 1> send_at{}, recv_at{};
    for (size_t q = 0; q < kFields; ++q) {
      send_at[q + 1] = send_at[q] + aligned(sends * int64_t(size[q]));
      recv_at[q + 1] = recv_at[q] + aligned(recvs * int64_t(size[q]));
    }
    reserve(send_at[kFields], send_buffer_);
    reserve(recv_at[kFields], recv_buffer_);
    if (link_) begin_side();
    size_t q = 0;
    (pack(fields, send_at[q++]), ...);

    // Field by field, a message per peer (the messages of a peer pair up in this order).
    const int ranks = comm_->size(), me = comm_->rank();
    char* send_base = send_buffer_.data();
    char* recv_base = recv_buffer_.data();
    if (Exec::kDevice && !link_) {  // staged: the packed values to host memory
      host_send_.resize(size_t(send_at[kFields]));
      host_recv_.resize(size_t(recv_at[kFields]));
      if (sends > 0) exec_->download(host_send_.data(), send_buffer_.data(), host_send_.size());
      send_base = host_send_.data();
      recv_base = host_recv_.data();
    }
    std::vector<DeviceLink::Transfer> link_send, link_recv;
    for (q = 0; q < kFields; ++q) {
      std::vector<Comm::Buffer> out(static_cast<size_t>(ranks)), in(static_cast<size_t>(ranks));
      for (int r = 0; r < ranks; ++r) {
        if (r == me) continue;
        const size_t s = size[q];
        out[size_t(r)] = {send_base + send_at[q] + send_first_[size_t(r)] * int64_t(s),
                          size_t(send_first_[size_t(r) + 1] - send_first_[size_t(r)]) * s};
        in[size_t(r)] = {recv_base + recv_at[q] + recv_first_[size_t(r)] * int64_t(s),
                         size_t(recv_first_[size_t(r) + 1] - recv_first_[size_t(r)]) * s};
        link_send.push_back({r, out[size_t(r)].data, out[size_t(r)].bytes});
        link_recv.push_back({r, in[size_t(r)].data, in[size_t(r)].bytes});
      }
      if (!link_) comm_->start_exchange(out, in);
    }
    if constexpr (Exec::kDevice)
      if (link_) link_->exchange(link_send, link_recv, exec_->stream());

    // The unpacking, queued now on the second stream or kept for finish().
    q = 0;
    unpack_.clear();
    (unpack_.push_back(unpacker(fields, recv_at[q++])), ...);
    if (link_) {
      for (auto& u : unpack_) u();
      unpack_.clear();
      end_side();
    }
    recv_bytes_ = recv_at[kFields];
    bytes_sent_ += sends * bytes_per_particle(size);
    ++exchanges_;
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  // After start(): the ghosts' values are in place for every launch queued from now on.
  void finish() {
    const auto t0 = std::chrono::steady_clock::now();
    if (link_) {
      wait_side();
    } else {
      comm_->finish_exchanges();
      if (Exec::kDevice && recv_bytes_ > 0)
        exec_->upload(recv_buffer_.data(), host_recv_.data(), size_t(recv_bytes_));
      for (auto& u : unpack_) u();
      unpack_.clear();
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  // Both at once.
  template <class T>
  void exchange(DeviceArray<T, Exec>& field) {
    start(field);
    finish();
  }

  // (Public only because CUDA's extended lambdas may not live in private member functions.)
  // The own values the peers read, packed at byte `at` of the send buffer.
  template <class T>
  void pack(DeviceArray<T, Exec>& field, int64_t at) {
    const int64_t sends = int64_t(send_index_.size());
    const ArrayView<const int32_t> index = view_of(send_index_);
    const ArrayView<const T> values = view_of(field);
    const ArrayView<T> packed{reinterpret_cast<T*>(send_buffer_.data() + at), sends};
    exec_->parallel_for("halo/pack", sends, [=] PD_HD(int64_t k) { packed[k] = values[index[k]]; });
  }

  // The received values at byte `at` of the receive buffer, written to the ghosts.
  template <class T>
  std::function<void()> unpacker(DeviceArray<T, Exec>& field, int64_t at) {
    const int64_t recvs = int64_t(recv_index_.size());
    const ArrayView<const int32_t> index = view_of(recv_index_);
    const ArrayView<T> values = view_of(field);
    const ArrayView<const T> unpacked{reinterpret_cast<const T*>(recv_buffer_.data() + at), recvs};
    Exec* exec = exec_;
    return [=] {
      exec->parallel_for("halo/unpack", recvs, [=] PD_HD(int64_t k) { values[index[k]] = unpacked[k]; });
    };
  }

 private:
  static int64_t aligned(int64_t bytes) { return (bytes + 15) / 16 * 16; }
  template <size_t kFields>
  static int64_t bytes_per_particle(const std::array<size_t, kFields>& size) {
    int64_t b = 0;
    for (size_t s : size) b += int64_t(s);
    return b;
  }

  void begin_side() {
    if constexpr (Exec::kDevice) exec_->begin_side();
  }
  void end_side() {
    if constexpr (Exec::kDevice) exec_->end_side();
  }
  void wait_side() {
    if constexpr (Exec::kDevice) exec_->wait_side();
  }

  // Per peer, its base list then its extra one, all peers in rank order.
  static void concatenate(const std::vector<std::vector<int32_t>>& base,
                          const std::vector<std::vector<int32_t>>& extra, std::vector<int32_t>& all,
                          std::vector<int64_t>& first) {
    first.assign(base.size() + 1, 0);
    for (size_t r = 0; r < base.size(); ++r) {
      all.insert(all.end(), base[r].begin(), base[r].end());
      all.insert(all.end(), extra[r].begin(), extra[r].end());
      first[r + 1] = int64_t(all.size());
    }
  }

  // A byte buffer of at least `bytes` (grown, never shrunk), 16-byte aligned as the backend
  // allocates. (Growing waits for the second stream, which may still read the old one.)
  void reserve(int64_t bytes, DeviceArray<char, Exec>& buffer) {
    if (int64_t(buffer.size()) >= bytes) return;
    if (link_) exec_->synchronize();
    buffer = DeviceArray<char, Exec>(exec_, size_t(bytes));
  }

  Exec* exec_ = nullptr;
  DeviceMemory<Exec>* mem_ = nullptr;
  Comm* comm_ = nullptr;
  std::unique_ptr<DeviceLink> link_;
  std::vector<std::vector<int32_t>> base_send_, base_recv_;  // the bond ghosts' lists
  DeviceArray<int32_t, Exec> send_index_, recv_index_;
  std::vector<int64_t> send_first_, recv_first_;
  DeviceArray<char, Exec> send_buffer_, recv_buffer_;
  std::vector<char> host_send_, host_recv_;    // staging, kept between exchanges
  std::vector<std::function<void()>> unpack_;  // a started exchange's unpacking, for finish()
  int64_t recv_bytes_ = 0;
  int64_t bytes_sent_ = 0, exchanges_ = 0;
  double seconds_ = 0;
};

}  // namespace pd
