// Non-template parts of the CUDA backend.
#include <cub/device/device_scan.cuh>

#include "cuda/exec_cuda.cuh"

namespace pd {

// What a user can do about a CUDA error of this kind.
const char* cuda_hint(cudaError_t err) {
  switch (err) {
    case cudaErrorMemoryAllocation:
      return "the GPU is out of memory: lower --scale or the particle count, free the GPU, or use --backend "
             "cpu";
    case cudaErrorNoDevice:
    case cudaErrorInsufficientDriver:
    case cudaErrorInvalidDevice:
    case cudaErrorNoKernelImageForDevice:
      return "no usable GPU for this build (it targets sm_90 unless configured with "
             "-DCMAKE_CUDA_ARCHITECTURES=...): use --backend cpu, or rebuild for this GPU";
    case cudaErrorLaunchOutOfResources:
    case cudaErrorInvalidConfiguration:
      return "the kernel could not be launched with this build's block size on this GPU: please report it "
             "with the output of `perifrac info`";
    case cudaErrorIllegalAddress:
    case cudaErrorMisalignedAddress:
    case cudaErrorLaunchFailure:
      return "a kernel accessed memory out of bounds or stopped at a failed bounds check: rerun under "
             "compute-sanitizer, or with the cuda-debug preset (bounds checks in kernel views; its message "
             "names the index and the place), and report it";
    default:
      return "see `perifrac info` for the device; --backend cpu runs without the GPU";
  }
}

void cuda_check(cudaError_t err, const char* what) {
  if (err == cudaSuccess) return;
  throw std::runtime_error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(err) + "; " +
                           cuda_hint(err));
}

CudaExec::CudaExec(KernelStats* stats) : stats_(stats) {}

CudaExec::~CudaExec() {
  cudaDeviceSynchronize();
  for (auto& p : pending_) {
    cudaEventDestroy(p.start);
    cudaEventDestroy(p.stop);
  }
  for (auto e : free_events_) cudaEventDestroy(e);
  for (void* s : scratch_) cudaFree(s);
  if (flag_host_) cudaFreeHost(flag_host_);
  for (cudaEvent_t e : flag_event_)
    if (e) cudaEventDestroy(e);
  for (auto& p : side_spans_) {
    cudaEventDestroy(p.start);
    cudaEventDestroy(p.stop);
  }
  if (fork_) cudaEventDestroy(fork_);
  if (join_) cudaEventDestroy(join_);
  if (side_) cudaStreamDestroy(side_);
  for (cudaGraphExec_t g : graphs_)
    if (g) cudaGraphExecDestroy(g);
  if (capture_) cudaStreamDestroy(capture_);
  if (read_start_) cudaEventDestroy(read_start_);
  if (reader_) cudaStreamDestroy(reader_);
}

CudaExec::ReadEvent::ReadEvent() {
  cuda_check(cudaEventCreateWithFlags(&event_, cudaEventDisableTiming), "read-back event");
}
CudaExec::ReadEvent::~ReadEvent() {
  cudaEventDestroy(event_);
}
void CudaExec::ReadEvent::wait() const {
  cuda_check(cudaEventSynchronize(event_), "a frame's read-back");
}

void* CudaExec::allocate_host(size_t bytes) {
  void* p = nullptr;
  const cudaError_t err = cudaHostAlloc(&p, bytes ? bytes : 1, cudaHostAllocDefault);
  if (err != cudaSuccess) {
    cudaGetLastError();  // (not left for the next launch's check to report)
    throw std::runtime_error("page-locked host memory of " + std::to_string(bytes) +
                             " bytes refused: " + cudaGetErrorString(err));
  }
  return p;
}
void CudaExec::release_host(void* p) {
  cudaFreeHost(p);
}

void CudaExec::read_back(const HostCopy* copies, int n, ReadEvent& done) {
  if (!reader_) {
    cuda_check(cudaStreamCreateWithFlags(&reader_, cudaStreamNonBlocking), "cudaStreamCreateWithFlags");
    cuda_check(cudaEventCreateWithFlags(&read_start_, cudaEventDisableTiming), "read-back event");
  }
  cuda_check(cudaEventRecord(read_start_, stream_), "read_back");
  cuda_check(cudaStreamWaitEvent(reader_, read_start_, 0), "read_back");
  for (int k = 0; k < n; ++k)
    cuda_check(
        cudaMemcpyAsync(copies[k].dst, copies[k].src, copies[k].bytes, cudaMemcpyDeviceToHost, reader_),
        "read_back");
  cuda_check(cudaEventRecord(done.event(), reader_), "read_back");
  cuda_check(cudaStreamWaitEvent(stream_, done.event(), 0), "read_back");
}

int CudaExec::device_count() const {
  int n = 0;
  cuda_check(cudaGetDeviceCount(&n), "cudaGetDeviceCount");
  return n;
}

void CudaExec::begin_side() {
  if (!side_) {
    cuda_check(cudaStreamCreateWithFlags(&side_, cudaStreamNonBlocking), "cudaStreamCreateWithFlags");
    cuda_check(cudaEventCreateWithFlags(&fork_, cudaEventDisableTiming), "cudaEventCreate");
    cuda_check(cudaEventCreateWithFlags(&join_, cudaEventDisableTiming), "cudaEventCreate");
  }
  cuda_check(cudaEventRecord(fork_, nullptr), "cudaEventRecord");
  cuda_check(cudaStreamWaitEvent(side_, fork_, 0), "cudaStreamWaitEvent");
  stream_ = side_;
  cudaEvent_t start = take_event();
  cuda_check(cudaEventRecord(start, side_), "cudaEventRecord");
  side_spans_.push_back({"side", start, nullptr});
}

void CudaExec::end_side() {
  cudaEvent_t stop = take_event();
  cuda_check(cudaEventRecord(stop, side_), "cudaEventRecord");
  side_spans_.back().stop = stop;
  cuda_check(cudaEventRecord(join_, side_), "cudaEventRecord");
  stream_ = nullptr;
}

void CudaExec::wait_side() {
  cuda_check(cudaStreamWaitEvent(nullptr, join_, 0), "cudaStreamWaitEvent");
}

// Capture goes to a stream of its own (the legacy default stream cannot capture), thread-local:
// a call of this thread that would wait for the device fails the capture instead.
void CudaExec::begin_capture() {
  if (!capture_)
    cuda_check(cudaStreamCreateWithFlags(&capture_, cudaStreamNonBlocking), "cudaStreamCreateWithFlags");
  cuda_check(cudaStreamBeginCapture(capture_, cudaStreamCaptureModeThreadLocal), "cudaStreamBeginCapture");
  stream_ = capture_;
  capture_stats_ = stats_;
  stats_ = nullptr;
}

void CudaExec::end_capture(int slot) {
  cudaGraph_t graph = nullptr;
  const cudaError_t ended = cudaStreamEndCapture(capture_, &graph);
  stream_ = nullptr;
  stats_ = capture_stats_;
  cuda_check(ended, "cudaStreamEndCapture");
  if (graphs_[slot]) cudaGraphExecDestroy(graphs_[slot]);
  graphs_[slot] = nullptr;
  const cudaError_t made = cudaGraphInstantiate(&graphs_[slot], graph, 0);
  cudaGraphDestroy(graph);
  cuda_check(made, "cudaGraphInstantiate");
}

void CudaExec::abort_capture() {
  if (stream_ != capture_ || !capture_) return;
  cudaGraph_t graph = nullptr;
  cudaStreamEndCapture(capture_, &graph);
  if (graph) cudaGraphDestroy(graph);
  cudaGetLastError();  // (the failed capture's error is the one being reported)
  stream_ = nullptr;
  stats_ = capture_stats_;
}

void CudaExec::drop_graphs() {
  for (cudaGraphExec_t& g : graphs_)
    if (g) {
      cudaGraphExecDestroy(g);
      g = nullptr;
    }
}

void CudaExec::launch_graph(int slot, const char* name) {
  cudaEvent_t start = begin_timing(name);
  cuda_check(cudaGraphLaunch(graphs_[slot], stream_), name);
  end_timing(name, start);
}

void CudaExec::describe(KernelStat* s, const void* kernel, int block) {
  cudaFuncAttributes attr{};
  cuda_check(cudaFuncGetAttributes(&attr, kernel), "cudaFuncGetAttributes");
  int blocks_per_sm = 0;
  cuda_check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks_per_sm, kernel, block, 0),
             "cudaOccupancyMaxActiveBlocksPerMultiprocessor");
  int device = 0, max_threads_per_sm = 0;
  cuda_check(cudaGetDevice(&device), "cudaGetDevice");
  cuda_check(cudaDeviceGetAttribute(&max_threads_per_sm, cudaDevAttrMaxThreadsPerMultiProcessor, device),
             "cudaDeviceGetAttribute");
  s->registers = attr.numRegs;
  s->block_size = block;
  s->occupancy = double(blocks_per_sm * block) / double(max_threads_per_sm);
}

int64_t CudaExec::resident_blocks(const void* kernel) const {
  int device = 0, sms = 0, per_sm = 0, cooperative = 0;
  cuda_check(cudaGetDevice(&device), "cudaGetDevice");
  cuda_check(cudaDeviceGetAttribute(&cooperative, cudaDevAttrCooperativeLaunch, device),
             "cudaDeviceGetAttribute");
  if (!cooperative) throw std::runtime_error("the GPU does not support cooperative launches");
  cuda_check(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device), "cudaDeviceGetAttribute");
  cuda_check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, kernel, kBlockSize, 0),
             "cudaOccupancyMaxActiveBlocksPerMultiprocessor");
  return std::max<int64_t>(int64_t(sms) * per_sm, 1);
}

cudaEvent_t CudaExec::take_event() {
  if (!free_events_.empty()) {
    cudaEvent_t e = free_events_.back();
    free_events_.pop_back();
    return e;
  }
  cudaEvent_t e;
  cuda_check(cudaEventCreate(&e), "cudaEventCreate");
  return e;
}

cudaEvent_t CudaExec::begin_timing(const char* name) {
  if (!stats_) return nullptr;
  if (stats_->entry(name).launches++ % kTimedLaunchStride != 0) return nullptr;
  cudaEvent_t e = take_event();
  cuda_check(cudaEventRecord(e, stream_), "cudaEventRecord");
  return e;
}

void CudaExec::end_timing(const char* name, cudaEvent_t start) {
  last_name_ = name;
  if (!start) return;
  cudaEvent_t stop = take_event();
  cuda_check(cudaEventRecord(stop, stream_), "cudaEventRecord");
  pending_.push_back({name, start, stop});
  // Bound the event backlog on long runs without a flush.
  if (pending_.size() >= 4096) flush_stats();
}

void CudaExec::flush_stats() {
  cudaError_t err = cudaDeviceSynchronize();
  if (err != cudaSuccess)
    throw std::runtime_error(std::string("CUDA error after kernel '") + last_name_ +
                             "': " + cudaGetErrorString(err) + "; " + cuda_hint(err));
  for (auto& p : pending_) {
    float ms = 0;
    cuda_check(cudaEventElapsedTime(&ms, p.start, p.stop), "cudaEventElapsedTime");
    KernelStat& s = stats_->entry(p.name);
    s.timed_seconds += 1e-3 * ms;
    ++s.timed_launches;
    free_events_.push_back(p.start);
    free_events_.push_back(p.stop);
  }
  pending_.clear();
  if (stats_) stats_->estimate_from_timed();
  // (A span still open, when a flush falls between begin_side and end_side, is kept.)
  const bool open = !side_spans_.empty() && !side_spans_.back().stop;
  for (size_t k = 0; k + (open ? 1 : 0) < side_spans_.size(); ++k) {
    const Pending& p = side_spans_[k];
    float ms = 0;
    cuda_check(cudaEventElapsedTime(&ms, p.start, p.stop), "cudaEventElapsedTime");
    side_seconds_ += 1e-3 * ms;
    free_events_.push_back(p.start);
    free_events_.push_back(p.stop);
  }
  side_spans_.erase(side_spans_.begin(), side_spans_.end() - (open ? 1 : 0));
}

void* CudaExec::scratch(int slot, size_t bytes) {
  if (bytes > scratch_bytes_[slot]) {
    cudaFree(scratch_[slot]);
    scratch_[slot] = nullptr;
    scratch_[slot] = allocate(bytes);
    scratch_bytes_[slot] = bytes;
  }
  return scratch_[slot];
}

void CudaExec::sort_by_key(const char* name, const uint32_t* key_in, const int32_t* val_in, uint32_t* key_out,
                           int32_t* val_out, int64_t n, uint32_t bins) {
  int bits = 1;
  while ((1ull << bits) < bins) ++bits;
  size_t temp_bytes = 0;
  cub::DeviceRadixSort::SortPairs(nullptr, temp_bytes, key_in, key_out, val_in, val_out, n, 0, bits);
  void* temp = scratch(0, temp_bytes);
  cudaEvent_t start = begin_timing(name);
  cuda_check(cub::DeviceRadixSort::SortPairs(temp, temp_bytes, key_in, key_out, val_in, val_out, n, 0, bits),
             name);
  end_timing(name, start);
}

int64_t CudaExec::exclusive_scan(const int64_t* in, int64_t* out, int64_t n) {
  if (n <= 0) return 0;
  size_t temp_bytes = 0;
  cub::DeviceScan::ExclusiveSum(nullptr, temp_bytes, in, out, n);
  void* temp = scratch(0, temp_bytes);
  cuda_check(cub::DeviceScan::ExclusiveSum(temp, temp_bytes, in, out, n), "exclusive_scan");
  int64_t last_in = 0, last_out = 0;
  cuda_check(cudaMemcpy(&last_in, in + n - 1, sizeof(int64_t), cudaMemcpyDeviceToHost), "exclusive_scan");
  cuda_check(cudaMemcpy(&last_out, out + n - 1, sizeof(int64_t), cudaMemcpyDeviceToHost), "exclusive_scan");
  return last_in + last_out;
}

void* CudaExec::allocate(size_t bytes) {
  void* p = nullptr;
  cudaError_t err = cudaMalloc(&p, bytes ? bytes : 1);
  if (err != cudaSuccess) {
    size_t free_b = 0, total_b = 0;
    cudaMemGetInfo(&free_b, &total_b);
    throw std::runtime_error("GPU allocation of " + std::to_string(bytes) + " bytes failed (" +
                             std::to_string(free_b >> 20) + " MiB free of " + std::to_string(total_b >> 20) +
                             " MiB): " + cudaGetErrorString(err) + "; " + cuda_hint(err));
  }
  return p;
}
void CudaExec::release(void* p) {
  cudaFree(p);
}
void CudaExec::upload(void* dst, const void* src, size_t bytes) {
  cuda_check(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice), "upload");
}
void CudaExec::download(void* dst, const void* src, size_t bytes) {
  cuda_check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost), "download");
}
void CudaExec::fill_bytes(void* dst, int value, size_t bytes) {
  cuda_check(cudaMemset(dst, value, bytes), "fill");
}
void CudaExec::synchronize() {
  cuda_check(cudaDeviceSynchronize(), "synchronize");
}

int32_t* CudaExec::flag(int k) {
  if (!flag_host_) {
    void* host = nullptr;
    cuda_check(cudaHostAlloc(&host, kFlags * sizeof(int32_t), cudaHostAllocMapped), "flags");
    flag_host_ = static_cast<int32_t*>(host);
    for (int q = 0; q < kFlags; ++q) flag_host_[q] = 0;
    void* device = nullptr;
    cuda_check(cudaHostGetDevicePointer(&device, host, 0), "flags");
    flag_device_ = static_cast<int32_t*>(device);
    for (cudaEvent_t& e : flag_event_)
      cuda_check(cudaEventCreateWithFlags(&e, cudaEventDisableTiming), "flags");
  }
  return flag_device_ + k;
}

void CudaExec::mark_flags(int event) {
  if (flag_host_) cuda_check(cudaEventRecord(flag_event_[event]), "flags");
}

uint32_t CudaExec::take_flags(uint32_t mask, int event) {
  if (!flag_host_) return 0;
  cuda_check(cudaEventSynchronize(flag_event_[event]), "a kernel before reading the kernels' flags");
  volatile int32_t* host = flag_host_;
  uint32_t raised = 0;
  for (int k = 0; k < kFlags; ++k) {
    if (!(mask >> k & 1u)) continue;
    raised |= uint32_t(host[k] != 0) << k;
    host[k] = 0;
  }
  return raised;
}

}  // namespace pd
