// The halo exchange of a partitioned run: each rank sends its own particles' values of a field to
// the ranks that hold them as ghosts, and receives its ghosts' values from their owners. Packed
// and unpacked by kernels on the backend, sent as one message per peer (cuda/parallel/comm.h);
// from the GPU, through host buffers.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "cuda/engine/device_memory.h"
#include "cuda/parallel/comm.h"
#include "cuda/parallel/partition.h"

namespace pd {

template <class Exec>
class Halo {
 public:
  Halo() = default;
  Halo(DeviceMemory<Exec>& mem, const RankLayout& layout, Comm& comm)
      : exec_(&mem.exec()), mem_(&mem), comm_(&comm), base_send_(layout.send), base_recv_(layout.recv) {
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
  int64_t bytes_sent() const { return bytes_sent_; }
  int64_t exchanges() const { return exchanges_; }
  double seconds() const { return seconds_; }

  // Every ghost's entry of `field` replaced by its owner's.
  template <class T>
  void exchange(DeviceArray<T, Exec>& field) {
    const auto t0 = std::chrono::steady_clock::now();
    const int64_t sends = int64_t(send_index_.size()), recvs = int64_t(recv_index_.size());
    reserve(sends * int64_t(sizeof(T)), send_buffer_);
    reserve(recvs * int64_t(sizeof(T)), recv_buffer_);
    const ArrayView<const int32_t> send_index = view_of(send_index_), recv_index = view_of(recv_index_);
    const ArrayView<T> values = view_of(field);
    const ArrayView<T> packed{reinterpret_cast<T*>(send_buffer_.data()), sends};
    exec_->parallel_for("halo/pack", sends, [=] PD_HD(int64_t k) { packed[k] = values[send_index[k]]; });
    // Host staging buffers kept between exchanges (their capacity is reused every step).
    std::vector<std::vector<char>>& out = host_out_;
    std::vector<std::vector<char>>& in = host_in_;
    std::vector<char>& host = host_;
    out.resize(size_t(comm_->size()));
    in.resize(size_t(comm_->size()));
    host.resize(size_t(sends) * sizeof(T));
    if (sends > 0) exec_->download(host.data(), send_buffer_.data(), host.size());
    for (size_t r = 0; r < out.size(); ++r) {
      out[r].assign(host.begin() + std::ptrdiff_t(send_first_[r] * int64_t(sizeof(T))),
                    host.begin() + std::ptrdiff_t(send_first_[r + 1] * int64_t(sizeof(T))));
      in[r].resize(size_t(recv_first_[r + 1] - recv_first_[r]) * sizeof(T));
    }
    comm_->exchange(out, in);
    host.resize(size_t(recvs) * sizeof(T));
    for (size_t r = 0; r < in.size(); ++r)
      std::copy(in[r].begin(), in[r].end(),
                host.begin() + std::ptrdiff_t(recv_first_[r] * int64_t(sizeof(T))));
    if (recvs > 0) exec_->upload(recv_buffer_.data(), host.data(), host.size());
    const ArrayView<const T> unpacked{reinterpret_cast<const T*>(recv_buffer_.data()), recvs};
    exec_->parallel_for("halo/unpack", recvs, [=] PD_HD(int64_t k) { values[recv_index[k]] = unpacked[k]; });
    bytes_sent_ += sends * int64_t(sizeof(T));
    ++exchanges_;
    exec_->synchronize();  // (the unpack, so the time is the exchange's)
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

 private:
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

  // A byte buffer of at least `bytes` (grown, never shrunk), 16-byte aligned as the backend allocates.
  void reserve(int64_t bytes, DeviceArray<char, Exec>& buffer) {
    if (int64_t(buffer.size()) >= bytes) return;
    buffer = DeviceArray<char, Exec>(exec_, size_t(bytes));
  }

  Exec* exec_ = nullptr;
  DeviceMemory<Exec>* mem_ = nullptr;
  Comm* comm_ = nullptr;
  std::vector<std::vector<int32_t>> base_send_, base_recv_;  // the bond ghosts' lists
  DeviceArray<int32_t, Exec> send_index_, recv_index_;
  std::vector<int64_t> send_first_, recv_first_;
  DeviceArray<char, Exec> send_buffer_, recv_buffer_;
  std::vector<std::vector<char>> host_out_, host_in_;
  std::vector<char> host_;
  int64_t bytes_sent_ = 0, exchanges_ = 0;
  double seconds_ = 0;
};

}  // namespace pd
