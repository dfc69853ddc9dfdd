// The ranks of a partitioned run and what they say to each other (cuda/parallel/): the few
// collective operations the partitioned engine uses, on byte buffers in host memory. One
// implementation talks MPI (comm_mpi.cpp, when the build finds MPI); without MPI there is no
// world to join and every run has one rank.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace pd {

class Comm {
 public:
  virtual ~Comm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // The rank's place among the ranks of its host (the GPU it takes), and how many share the host.
  virtual int local_rank() const = 0;
  virtual int local_size() const = 0;

  // `bytes` at `data` on `root` copied to every rank's `data`.
  virtual void broadcast(void* data, size_t bytes, int root) = 0;
  // Every rank's value combined, on every rank.
  virtual int64_t sum(int64_t value) = 0;
  virtual double min(double value) = 0;
  virtual double max(double value) = 0;
  virtual uint32_t bit_or(uint32_t value) = 0;
  // Point to point with every other rank at once, split so that work goes on while the messages
  // travel: start_exchange posts a send and a receive per peer (send[r] to rank r, recv[r] from
  // it; empty ones skipped) and returns; finish_exchanges waits for every one started. The
  // buffers stay untouched until then. Several may be started before one finish: the messages of
  // one peer pair up in the order started.
  struct Buffer {
    char* data = nullptr;
    size_t bytes = 0;
  };
  virtual void start_exchange(const std::vector<Buffer>& send, const std::vector<Buffer>& recv) = 0;
  virtual void finish_exchanges() = 0;
  // The same at once: send[r] goes to rank r and recv[r] (sized by the caller, the length rank r
  // sends) is filled from it. Empty buffers are skipped.
  void exchange(const std::vector<std::vector<char>>& send, std::vector<std::vector<char>>& recv) {
    std::vector<Buffer> out(send.size()), in(recv.size());
    for (size_t r = 0; r < send.size(); ++r) out[r] = {const_cast<char*>(send[r].data()), send[r].size()};
    for (size_t r = 0; r < recv.size(); ++r) in[r] = {recv[r].data(), recv[r].size()};
    start_exchange(out, in);
    finish_exchanges();
  }
  // Every rank's `data` on `root`, one buffer per rank (of any length); other ranks get nothing.
  virtual void gather(const std::vector<char>& data, std::vector<std::vector<char>>& out, int root) = 0;
  // Ends every rank's process with `code` (an error on one rank that the others cannot see).
  [[noreturn]] virtual void abort(int code) = 0;
};

// The world this process was started in: a Comm when started by mpirun (or another MPI launcher)
// with more than one rank, otherwise null. MPI is initialised on the first call and finalised
// at exit.
std::shared_ptr<Comm> world_comm();

// Ends this process's part of the world (MPI_Finalize) before it exits; nothing without one.
void leave_world();

// Whether the build can join an MPI world at all.
bool mpi_available();

// Typed helpers over the byte buffers.
template <class T>
std::vector<char> to_bytes(const std::vector<T>& v) {
  std::vector<char> b(v.size() * sizeof(T));
  if (!b.empty()) std::memcpy(b.data(), v.data(), b.size());
  return b;
}
template <class T>
std::vector<T> from_bytes(const std::vector<char>& b) {
  std::vector<T> v(b.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), b.data(), v.size() * sizeof(T));
  return v;
}

}  // namespace pd
