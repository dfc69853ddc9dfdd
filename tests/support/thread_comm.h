// Ranks as threads of one process for tests of the partitioned engine's parts (cuda/parallel/):
// a Comm whose point-to-point messages go through in-memory queues. The collectives the halo and
// the contact ghosts do not use throw.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cuda/parallel/comm.h"

namespace pd {

// Messages between threads: a queue per (from, to), received in the order sent.
struct Mailboxes {
  std::mutex m;
  std::condition_variable cv;
  std::map<std::pair<int, int>, std::deque<std::vector<char>>> box;
};

class ThreadComm final : public Comm {
 public:
  ThreadComm(Mailboxes& mail, int rank, int size) : mail_(mail), rank_(rank), size_(size) {}
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int local_rank() const override { return rank_; }
  int local_size() const override { return size_; }
  void broadcast(void*, size_t, int) override { unused(); }
  int64_t sum(int64_t) override { unused(); }
  double min(double) override { unused(); }
  double max(double) override { unused(); }
  uint32_t bit_or(uint32_t) override { unused(); }
  void gather(const std::vector<char>&, std::vector<std::vector<char>>&, int) override { unused(); }
  [[noreturn]] void abort(int) override { unused(); }
  void start_exchange(const std::vector<Buffer>& send, const std::vector<Buffer>& recv) override {
    std::lock_guard<std::mutex> lock(mail_.m);
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) continue;
      const Buffer& b = send[size_t(r)];
      if (b.bytes > 0) mail_.box[{rank_, r}].emplace_back(b.data, b.data + b.bytes);
      if (recv[size_t(r)].bytes > 0) pending_.push_back({r, recv[size_t(r)]});
    }
    mail_.cv.notify_all();
  }

  void finish_exchanges() override {
    std::unique_lock<std::mutex> lock(mail_.m);
    for (const auto& [from, buffer] : pending_) {
      auto& q = mail_.box[{from, rank_}];
      mail_.cv.wait(lock, [&] { return !q.empty(); });
      if (q.front().size() != buffer.bytes) throw std::logic_error("message of the wrong length");
      std::copy(q.front().begin(), q.front().end(), buffer.data);
      q.pop_front();
    }
    pending_.clear();
  }

 private:
  [[noreturn]] static void unused() {
    throw std::logic_error("not used by the halo and contact ghosts on CPU ranks");
  }
  Mailboxes& mail_;
  int rank_, size_;
  std::vector<std::pair<int, Buffer>> pending_;
};

}  // namespace pd
