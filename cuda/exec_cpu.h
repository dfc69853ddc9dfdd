// CPU-reference backend: parallel_for is an OpenMP loop over the same PD_HD kernel bodies
// the GPU runs. Memory is plain host memory.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <new>
#include <vector>

#include "cuda/kernel_stats.h"
#include "cuda/pd_common.h"
#include "cuda/read_back.h"

namespace pd {

class CpuExec {
 public:
  static constexpr bool kDevice = false;
  static constexpr bool kGraphs = false;  // (CUDA graphs of the step: exec_cuda.cuh)

  explicit CpuExec(KernelStats* stats) : stats_(stats) {}

  // The GPU's threads per block of team launches (CudaExec::set_team_block); no meaning here.
  void set_team_block(int) {}
  // Overlapped launches (CudaExec::set_overlap_launches); no meaning here.
  void set_overlap_launches(bool) {}

  // Loops shorter than this run on the calling thread: waking the team costs more than they take,
  // and far more on a busy machine, where a team waits for its descheduled threads. (Each f(i)
  // writes its own outputs, so the bits do not depend on it.)
  static constexpr int64_t kParallelMinimum = 1024;

  // kMinBlocks: the GPU backend's occupancy hint (CudaExec::parallel_for); no meaning here.
  template <int kMinBlocks = 0, class F>
  void parallel_for(const char* name, int64_t n, F f) {
    const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(static) if (n >= kParallelMinimum)
    for (int64_t i = 0; i < n; ++i) f(i);
    record(name, t0);
  }

  // f(i) for i in [first, first + n).
  template <int kMinBlocks = 0, class F>
  void parallel_for_from(const char* name, int64_t first, int64_t n, F f) {
    if (first == 0) return parallel_for<kMinBlocks>(name, n, f);
    parallel_for<kMinBlocks>(name, n, [&](int64_t k) { f(first + k); });
  }

  // Phase k runs f_k(i) for i in [0, n[k]), all of it before phase k + 1 (CudaExec: in one
  // launch); counted and timed as one launch.
  template <class... F>
  void parallel_phases(const char* name, const std::array<int64_t, sizeof...(F)>& n, F... f) {
    const auto t0 = std::chrono::steady_clock::now();
    size_t k = 0;
    const auto run = [&](auto& phase) {
      const int64_t count = n[k++];
#pragma omp parallel for schedule(static) if (count >= kParallelMinimum)
      for (int64_t i = 0; i < count; ++i) phase(i);
    };
    (run(f), ...);
    record(name, t0);
  }

  // Sum of f(i) over [0, n) for any type with +: per-thread partial sums over static
  // chunks, added in thread order, so the result is deterministic for a thread count.
  template <class T, class F>
  T reduce_sum(const char* name, int64_t n, F f) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<T> partial(static_cast<size_t>(omp_get_max_threads()));
#pragma omp parallel
    {
      T local{};
#pragma omp for schedule(static)
      for (int64_t i = 0; i < n; ++i) local = local + f(i);
      partial[size_t(omp_get_thread_num())] = local;
    }
    T total{};
    for (const T& t : partial) total = total + t;
    record(name, t0);
    return total;
  }

  // Stable sort of (key, value) pairs by key, keys < `bins`: a counting sort.
  void sort_by_key(const char* name, const uint32_t* key_in, const int32_t* val_in, uint32_t* key_out,
                   int32_t* val_out, int64_t n, uint32_t bins) {
    const auto t0 = std::chrono::steady_clock::now();
    histogram_.assign(size_t(bins) + 1, 0);
    for (int64_t i = 0; i < n; ++i) ++histogram_[key_in[i] + 1];
    for (uint32_t b = 0; b < bins; ++b) histogram_[b + 1] += histogram_[b];
    for (int64_t i = 0; i < n; ++i) {
      const int64_t dst = histogram_[key_in[i]]++;
      key_out[dst] = key_in[i];
      val_out[dst] = val_in[i];
    }
    record(name, t0);
  }

  // out[i] = sum of in[0..i); returns the total.
  int64_t exclusive_scan(const int64_t* in, int64_t* out, int64_t n) {
    int64_t running = 0;
    for (int64_t i = 0; i < n; ++i) {
      const int64_t v = in[i];
      out[i] = running;
      running += v;
    }
    return running;
  }

  void* allocate(size_t bytes) {
    void* p = std::malloc(bytes ? bytes : 1);
    if (!p) throw std::bad_alloc();
    return p;
  }
  void release(void* p) {
    std::free(p);
  }
  void upload(void* dst, const void* src, size_t bytes) {
    std::memcpy(dst, src, bytes);
  }
  void download(void* dst, const void* src, size_t bytes) {
    std::memcpy(dst, src, bytes);
  }
  void fill_bytes(void* dst, int value, size_t bytes) {
    std::memset(dst, value, bytes);
  }
  void synchronize() {}
  void flush_stats() {}

  // A read-back beside later launches (CudaExec::read_back): here the copies are made at once.
  class ReadEvent {
   public:
    void wait() const {}
  };
  void* allocate_host(size_t bytes) {
    return allocate(bytes);
  }
  static void release_host(void* p) {
    std::free(p);
  }
  void read_back(const HostCopy* copies, int n, ReadEvent&) {
    for (int k = 0; k < n; ++k) std::memcpy(copies[k].dst, copies[k].src, copies[k].bytes);
  }

  // Flags the kernels raise (raise_flag) and the host reads: flag(k) for k < kFlags;
  // mark_flags(e) after the launches that may raise them (event e < kFlagEvents), take_flags(mask,
  // e) waits for those launches and returns the raised flags of mask as bits (bit k: flag k),
  // those cleared.
  static constexpr int kFlags = 6;
  static constexpr int kFlagEvents = 3;
  int32_t* flag(int k) {
    return &flags_[k];
  }
  void mark_flags(int) {}
  uint32_t take_flags(uint32_t mask, int) {
    uint32_t raised = 0;
    for (int k = 0; k < kFlags; ++k) {
      if (!(mask >> k & 1u)) continue;
      raised |= uint32_t(flags_[k] != 0) << k;
      flags_[k] = 0;
    }
    return raised;
  }

 private:
  void record(const char* name, std::chrono::steady_clock::time_point t0) {
    if (!stats_) return;
    KernelStat& s = stats_->entry(name);
    s.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++s.launches;
  }

  KernelStats* stats_;
  std::vector<int64_t> histogram_;
  int32_t flags_[kFlags] = {};
};

}  // namespace pd
