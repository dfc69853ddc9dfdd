// CUDA backend: parallel_for launches one thread per item on a grid; one launch in
// kTimedLaunchStride of each kernel is timed with CUDA events, resolved in flush_stats(). Sorting,
// scans and reductions use CUB.
#pragma once

#include <cooperative_groups.h>
#include <cuda_runtime.h>

#include <algorithm>
#include <array>
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_reduce.cuh>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/kernel_stats.h"
#include "cuda/pd_common.h"
#include "cuda/read_back.h"
#include "cuda/team.h"

namespace pd {

void cuda_check(cudaError_t err, const char* what);

// Programmatic dependent launch (sm_90, CUDA's PDL): the step's kernels are launched so that
// the next one's blocks may be scheduled while this one's last blocks run (CudaExec::launch), which
// hides the gap between two launches. Each kernel of parallel_for & co. first waits until the
// launch before it has finished and its writes are visible (griddepcontrol.wait: at once for a
// launch made without the attribute), then lets the launch after it be scheduled
// (griddepcontrol.launch_dependents), so nothing a kernel reads or writes can race with the
// launch before it, and every result is the one of launches in turn.
__device__ inline void follow_previous_launch() {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
  asm volatile("griddepcontrol.wait;" ::: "memory");
  asm volatile("griddepcontrol.launch_dependents;" :::);
#endif
}

template <class F>
__global__ void parallel_for_kernel(int64_t n, F f) {
  follow_previous_launch();
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

constexpr int kCudaBlockSize = 256;  // threads per block of every launch

// The same with an occupancy floor: at least kMinBlocks blocks per SM, which caps the registers
// per thread (65536 / (kMinBlocks * kCudaBlockSize)).
template <int kMinBlocks, class F>
__global__ void __launch_bounds__(kCudaBlockSize, kMinBlocks) parallel_for_bounded_kernel(int64_t n, F f) {
  follow_previous_launch();
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

// Both over [first, first + n) (parallel_for_from).
template <class F>
__global__ void parallel_for_from_kernel(int64_t first, int64_t n, F f) {
  follow_previous_launch();
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(first + i);
}

template <int kMinBlocks, class F>
__global__ void __launch_bounds__(kCudaBlockSize, kMinBlocks)
    parallel_for_from_bounded_kernel(int64_t first, int64_t n, F f) {
  follow_previous_launch();
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(first + i);
}

// Teams of kThreads lanes (team.h), item first + t for team t: f(first + t, team). Teams never
// straddle a warp, and a team is wholly in or out of range.
template <int kThreads, int kMinBlocks, class F>
__global__ void __launch_bounds__(kCudaBlockSize, kMinBlocks > 0 ? kMinBlocks : 1)
    parallel_for_team_kernel(int64_t first, int64_t n, F f) {
  follow_previous_launch();
  const int64_t thread = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  const int64_t t = thread / kThreads;
  if (t >= n) return;
  const int32_t lane = int32_t(threadIdx.x % kThreads);
  const uint32_t team_mask = (kThreads == 32 ? ~0u : (1u << kThreads) - 1u)
                             << ((threadIdx.x & 31u) & ~uint32_t(kThreads - 1));
  f(first + t, Team<kThreads>{lane, team_mask});
}

// Phases of one cooperative launch (CudaExec::parallel_phases): each thread strides over phase
// k's items, then the whole grid waits for the others before phase k + 1.
template <size_t kPhases>
struct PhaseCounts {
  int64_t n[kPhases];
};

template <class... F>
__global__ void parallel_phases_kernel(PhaseCounts<sizeof...(F)> counts, F... f) {
  const cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  const int64_t first = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  const int64_t stride = int64_t(gridDim.x) * blockDim.x;
  size_t k = 0;
  const auto run = [&](auto& phase) {
    if (k > 0) grid.sync();
    for (int64_t i = first; i < counts.n[k]; i += stride) phase(i);
    ++k;
  };
  (run(f), ...);
}

template <class T, class F>
__global__ void transform_kernel(int64_t n, F f, T* out) {
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) out[i] = f(i);
}

class CudaExec {
 public:
  static constexpr bool kDevice = true;
  static constexpr int kBlockSize = kCudaBlockSize;

  explicit CudaExec(KernelStats* stats);

  // Threads per block of the team launches: kBlockSize, or 128 (team.h team_block_for). The same
  // kernels (their register bound is for kBlockSize, which any smaller block keeps) and the same
  // bits: a team's sums are its own and a launch's particles its own, whatever the blocks.
  void set_team_block(int threads) { team_block_ = threads; }
  // Whether launches overlap their predecessor's last blocks (launch; on unless switched off
  // with PERIFRAC_OVERLAP_LAUNCHES=off, step_graphs.h): the same bits either way.
  void set_overlap_launches(bool on) { overlap_launches_ = on; }
  ~CudaExec();
  CudaExec(const CudaExec&) = delete;
  CudaExec& operator=(const CudaExec&) = delete;

  // kMinBlocks > 0: keep at least that many blocks resident per SM (registers capped to fit),
  // for kernels whose speed follows their occupancy (bench/NOTES.md).
  template <int kMinBlocks = 0, class F>
  void parallel_for(const char* name, int64_t n, F f) {
    if (n <= 0) return;
    KernelStat* s = stats_ ? &stats_->entry(name) : nullptr;
    const int64_t blocks = (n + kBlockSize - 1) / kBlockSize;
    if constexpr (kMinBlocks > 0) {
      if (s && s->registers < 0)
        describe(s, reinterpret_cast<const void*>(&parallel_for_bounded_kernel<kMinBlocks, F>));
    } else {
      if (s && s->registers < 0) describe(s, reinterpret_cast<const void*>(&parallel_for_kernel<F>));
    }
    cudaEvent_t start = begin_timing(name);
    if constexpr (kMinBlocks > 0)
      launch(name, parallel_for_bounded_kernel<kMinBlocks, F>, blocks, kBlockSize, n, f);
    else
      launch(name, parallel_for_kernel<F>, blocks, kBlockSize, n, f);
    end_timing(name, start);
  }

  // f(i) for i in [first, first + n) (a partitioned rank's interior or boundary particles). From
  // 0 it is parallel_for's very launch, so a run over all particles keeps that kernel's code.
  template <int kMinBlocks = 0, class F>
  void parallel_for_from(const char* name, int64_t first, int64_t n, F f) {
    if (first == 0) return parallel_for<kMinBlocks>(name, n, f);
    if (n <= 0) return;
    const int64_t blocks = (n + kBlockSize - 1) / kBlockSize;
    cudaEvent_t start = begin_timing(name);
    if constexpr (kMinBlocks > 0)
      launch(name, parallel_for_from_bounded_kernel<kMinBlocks, F>, blocks, kBlockSize, first, n, f);
    else
      launch(name, parallel_for_from_kernel<F>, blocks, kBlockSize, first, n, f);
    end_timing(name, start);
  }

  // f(i, team) for i in [first, first + n), each i run by a team of kThreads > 1 threads
  // (team.h; the CPU backend has one thread per item, and launches of Team<1> use parallel_for),
  // in blocks of set_team_block's threads.
  template <int kThreads, int kMinBlocks = 0, class F>
  void parallel_for_team(const char* name, int64_t first, int64_t n, F f) {
    static_assert(kThreads > 1);
    if (n <= 0) return;
    KernelStat* s = stats_ ? &stats_->entry(name) : nullptr;
    if (s && s->registers < 0)
      describe(s, reinterpret_cast<const void*>(&parallel_for_team_kernel<kThreads, kMinBlocks, F>),
               team_block_);
    const int64_t blocks = (n * kThreads + team_block_ - 1) / team_block_;
    cudaEvent_t start = begin_timing(name);
    launch(name, parallel_for_team_kernel<kThreads, kMinBlocks, F>, blocks, team_block_, first, n, f);
    end_timing(name, start);
  }

  // Phase k runs f_k(i) for i in [0, n[k]), all of it before phase k + 1: one cooperative launch
  // of as many blocks as the largest phase needs and the GPU holds at once, a grid-wide barrier
  // between the phases. For chains of small passes whose launches cost more than their work
  // (bench/NOTES.md: the contact lists' relisting rounds).
  template <class... F>
  void parallel_phases(const char* name, const std::array<int64_t, sizeof...(F)>& n, F... f) {
    const int64_t most = *std::max_element(n.begin(), n.end());
    if (most <= 0) return;
    const void* kernel = reinterpret_cast<const void*>(&parallel_phases_kernel<F...>);
    KernelStat* s = stats_ ? &stats_->entry(name) : nullptr;
    if (s && s->registers < 0) describe(s, kernel);
    static const int64_t resident = resident_blocks(kernel);  // (per instantiation: one device per process)
    const int64_t blocks = std::min((most + kBlockSize - 1) / kBlockSize, resident);
    PhaseCounts<sizeof...(F)> counts;
    for (size_t k = 0; k < n.size(); ++k) counts.n[k] = n[k];
    void* args[] = {&counts, &f...};
    cudaEvent_t start = begin_timing(name);
    cuda_check(
        cudaLaunchCooperativeKernel(kernel, dim3(unsigned(blocks)), dim3(kBlockSize), args, 0, stream_),
        name);
    end_timing(name, start);
  }

  template <class T, class F>
  T reduce_sum(const char* name, int64_t n, F f) {
    if (n <= 0) return T{};
    T* values = static_cast<T*>(scratch(0, sizeof(T) * size_t(n)));
    const int64_t blocks = (n + kBlockSize - 1) / kBlockSize;
    cudaEvent_t start = begin_timing(name);
    transform_kernel<T><<<unsigned(blocks), kBlockSize>>>(n, f, values);
    cuda_check(cudaGetLastError(), name);
    T* total = static_cast<T*>(scratch(1, sizeof(T)));
    size_t temp_bytes = 0;
    cub::DeviceReduce::Sum(nullptr, temp_bytes, values, total, n);
    void* temp = scratch(2, temp_bytes);
    cuda_check(cub::DeviceReduce::Sum(temp, temp_bytes, values, total, n), name);
    end_timing(name, start);
    T host{};
    cuda_check(cudaMemcpy(&host, total, sizeof(T), cudaMemcpyDeviceToHost), name);
    return host;
  }

  void sort_by_key(const char* name, const uint32_t* key_in, const int32_t* val_in, uint32_t* key_out,
                   int32_t* val_out, int64_t n, uint32_t bins);
  int64_t exclusive_scan(const int64_t* in, int64_t* out, int64_t n);

  void* allocate(size_t bytes);
  void release(void* p);
  void upload(void* dst, const void* src, size_t bytes);
  void download(void* dst, const void* src, size_t bytes);
  void fill_bytes(void* dst, int value, size_t bytes);
  void synchronize();
  // Flags the kernels raise (raise_flag) and the host reads without a copy (mapped host memory):
  // flag(k) for k < kFlags; mark_flags(e) after the launches that may raise them (event e <
  // kFlagEvents), take_flags(mask, e) waits for the launches before the last mark_flags(e) (an
  // event, so later launches keep running) and returns the raised flags of mask as bits (bit k:
  // flag k), those cleared.
  static constexpr int kFlags = 6;
  static constexpr int kFlagEvents = 3;
  int32_t* flag(int k);
  void mark_flags(int event);
  uint32_t take_flags(uint32_t mask, int event);
  // A second stream for work that overlaps the main one's (a partitioned run's halo): the
  // launches between begin_side() and end_side() go to it, after everything queued on the main
  // stream before begin_side(); wait_side() makes main-stream work queued after it wait for them.
  // stream() is the stream launches go to now (a cudaStream_t); side_seconds() the side's time
  // (between begin_side and end_side) up to the last flush_stats.
  void begin_side();
  void end_side();
  void wait_side();
  void* stream() { return stream_; }
  // CUDA graphs (the engine's step, step_graphs.h): the launches between begin_capture() and
  // end_capture(slot) are recorded into a graph, not run; launch_graph(slot, name) runs it as one
  // launch, counted and timed as `name`. While capturing nothing may wait for the device and the
  // launches are neither counted nor timed; abort_capture() ends a capture that failed.
  static constexpr bool kGraphs = true;
  static constexpr int kGraphSlots = 4;
  void begin_capture();
  void end_capture(int slot);
  void abort_capture();
  bool has_graph(int slot) const { return graphs_[slot] != nullptr; }
  void drop_graphs();
  void launch_graph(int slot, const char* name);
  // Device-to-host copies beside later launches (Engine::read_frame): read_back(copies, n, done)
  // queues the copies into page-locked host memory (allocate_host) on a stream of their own, after
  // the launches queued so far; later launches wait for them on the device (they could change what
  // is being read), the host does not. done.wait() (any thread) returns once they are in host
  // memory. An event is recorded again only after its wait.
  class ReadEvent {
   public:
    ReadEvent();
    ~ReadEvent();
    ReadEvent(const ReadEvent&) = delete;
    ReadEvent& operator=(const ReadEvent&) = delete;
    void wait() const;
    cudaEvent_t event() const { return event_; }

   private:
    cudaEvent_t event_ = nullptr;
  };
  void* allocate_host(size_t bytes);  // std::runtime_error when refused
  static void release_host(void* p);
  void read_back(const HostCopy* copies, int n, ReadEvent& done);
  int device_count() const;  // GPUs this process sees
  double side_seconds() const { return side_seconds_; }
  // Waits for the device, adds the timed launches to the stats, and reports any
  // asynchronous kernel error with the name of the kernel family last launched.
  void flush_stats();

 private:
  struct Pending {
    const char* name;
    cudaEvent_t start, stop;
  };
  // kernel<<<blocks, threads, 0, stream_>>>(args...) as a programmatic dependent launch
  // (follow_previous_launch) where overlap_launches_; its error named after the launch's kernel.
  template <class... Params, class... Args>
  void launch(const char* name, void (*kernel)(Params...), int64_t blocks, int threads, const Args&... args) {
    cudaLaunchAttribute overlap{};
    overlap.id = cudaLaunchAttributeProgrammaticStreamSerialization;
    overlap.val.programmaticStreamSerializationAllowed = 1;
    cudaLaunchConfig_t config{};
    config.gridDim = dim3(unsigned(blocks));
    config.blockDim = dim3(unsigned(threads));
    config.stream = stream_;
    config.attrs = &overlap;
    config.numAttrs = overlap_launches_ ? 1 : 0;
    cuda_check(cudaLaunchKernelEx(&config, kernel, args...), name);
  }
  void describe(KernelStat* s, const void* kernel, int block = kBlockSize);
  int64_t resident_blocks(const void* kernel) const;  // blocks of `kernel` the GPU holds at once
  cudaEvent_t begin_timing(const char* name);         // counts the launch; an event where it is timed
  void end_timing(const char* name, cudaEvent_t start);
  cudaEvent_t take_event();
  void* scratch(int slot, size_t bytes);

  KernelStats* stats_;
  int team_block_ = kBlockSize;
  bool overlap_launches_ = true;  // (launch)
  std::vector<Pending> pending_;
  std::vector<cudaEvent_t> free_events_;
  void* scratch_[3] = {nullptr, nullptr, nullptr};
  size_t scratch_bytes_[3] = {0, 0, 0};
  const char* last_name_ = "";
  int32_t* flag_host_ = nullptr;
  int32_t* flag_device_ = nullptr;
  cudaEvent_t flag_event_[kFlagEvents] = {};
  cudaStream_t stream_ = nullptr;  // where launches go: the main (legacy default) stream or the side
  cudaStream_t side_ = nullptr;
  cudaEvent_t fork_ = nullptr, join_ = nullptr;
  std::vector<Pending> side_spans_;  // begin_side to end_side, resolved in flush_stats
  double side_seconds_ = 0;
  cudaStream_t reader_ = nullptr;         // read_back's copies
  cudaEvent_t read_start_ = nullptr;      // the main stream's launches before a read-back
  cudaStream_t capture_ = nullptr;        // where a graph's launches are recorded
  KernelStats* capture_stats_ = nullptr;  // stats_ while capturing
  cudaGraphExec_t graphs_[kGraphSlots] = {};
};

}  // namespace pd
