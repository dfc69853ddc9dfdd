// Comm over MPI: joined only when an MPI launcher started this process with more than one rank,
// so a plain run never initialises MPI. Messages larger than MPI's int count are sent in pieces.
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cuda/parallel/comm.h"

namespace pd {

namespace {

constexpr size_t kPiece = size_t(1) << 30;  // bytes per MPI call

// The world size an MPI launcher announced in the environment (0: not started by one).
int launched_world_size() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"}) {
    if (const char* v = std::getenv(var)) return std::max(0, std::atoi(v));
  }
  return 0;
}

int launched_local_size() {
  for (const char* var : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}) {
    if (const char* v = std::getenv(var)) return std::max(1, std::atoi(v));
  }
  return 1;
}

int launched_local_rank() {
  for (const char* var : {"OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "SLURM_LOCALID"}) {
    if (const char* v = std::getenv(var)) return std::max(0, std::atoi(v));
  }
  return 0;
}

void check(int err, const char* what) {
  if (err == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(err, text, &len);
  std::fprintf(stderr, "error: MPI %s failed: %s\n", what, text);
  MPI_Abort(MPI_COMM_WORLD, 5);
  std::abort();
}

class MpiComm final : public Comm {
 public:
  MpiComm() {
    int provided = 0;
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "init");
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    local_rank_ = launched_local_rank();
    local_size_ = launched_local_size();
  }
  ~MpiComm() override { leave_world(); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int local_rank() const override { return local_rank_; }
  int local_size() const override { return local_size_; }

  void broadcast(void* data, size_t bytes, int root) override {
    char* p = static_cast<char*>(data);
    for (size_t at = 0; at < bytes; at += kPiece)
      check(MPI_Bcast(p + at, int(std::min(kPiece, bytes - at)), MPI_BYTE, root, MPI_COMM_WORLD),
            "broadcast");
  }

  int64_t sum(int64_t value) override {
    int64_t out = 0;
    check(MPI_Allreduce(&value, &out, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD), "sum");
    return out;
  }
  double min(double value) override { return reduce(value, MPI_MIN); }
  double max(double value) override { return reduce(value, MPI_MAX); }
  uint32_t bit_or(uint32_t value) override {
    uint32_t out = 0;
    check(MPI_Allreduce(&value, &out, 1, MPI_UINT32_T, MPI_BOR, MPI_COMM_WORLD), "or");
    return out;
  }

  void start_exchange(const std::vector<Buffer>& send, const std::vector<Buffer>& recv) override {
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) continue;
      post(send[size_t(r)].data, send[size_t(r)].bytes, r, true, pending_);
      post(recv[size_t(r)].data, recv[size_t(r)].bytes, r, false, pending_);
    }
  }

  void finish_exchanges() override {
    check(MPI_Waitall(int(pending_.size()), pending_.data(), MPI_STATUSES_IGNORE), "exchange");
    pending_.clear();
  }

  void gather(const std::vector<char>& data, std::vector<std::vector<char>>& out, int root) override {
    const uint64_t mine = data.size();
    std::vector<uint64_t> sizes(size_t(size_), 0);
    check(MPI_Gather(&mine, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, root, MPI_COMM_WORLD), "gather");
    std::vector<MPI_Request> requests;
    if (rank_ == root) {
      out.assign(size_t(size_), {});
      for (int r = 0; r < size_; ++r) {
        out[size_t(r)].resize(sizes[size_t(r)]);
        if (r == root)
          out[size_t(r)] = data;
        else
          post(out[size_t(r)].data(), out[size_t(r)].size(), r, false, requests);
      }
    } else {
      out.clear();
      post(const_cast<char*>(data.data()), data.size(), root, true, requests);
    }
    check(MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "gather");
  }

  [[noreturn]] void abort(int code) override {
    std::fflush(stdout);
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
  }

 private:
  double reduce(double value, MPI_Op op) {
    double out = 0;
    check(MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, op, MPI_COMM_WORLD), "reduce");
    return out;
  }

  // Non-blocking send or receive of `bytes` in pieces (tagged by piece, so they pair up in order).
  void post(char* p, size_t bytes, int peer, bool send, std::vector<MPI_Request>& requests) {
    int tag = 0;
    for (size_t at = 0; at < bytes; at += kPiece, ++tag) {
      MPI_Request r;
      const int count = int(std::min(kPiece, bytes - at));
      check(send ? MPI_Isend(p + at, count, MPI_BYTE, peer, tag, MPI_COMM_WORLD, &r)
                 : MPI_Irecv(p + at, count, MPI_BYTE, peer, tag, MPI_COMM_WORLD, &r),
            send ? "send" : "receive");
      requests.push_back(r);
    }
  }

  int rank_ = 0, size_ = 1, local_rank_ = 0, local_size_ = 1;
  std::vector<MPI_Request> pending_;  // started exchanges' requests
};

}  // namespace

bool mpi_available() {
  return true;
}

void leave_world() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (initialized && !finalized) MPI_Finalize();
}

std::shared_ptr<Comm> world_comm() {
  static std::shared_ptr<Comm> world = []() -> std::shared_ptr<Comm> {
    if (launched_world_size() <= 1) return nullptr;
    return std::make_shared<MpiComm>();
  }();
  return world;
}

}  // namespace pd
