// The CUDA engine: the shared kernel bodies launched one particle per thread.
#include <nvtx3/nvToolsExt.h>

#include "cuda/engine/engine_impl.h"
#include "cuda/exec_cuda.cuh"
#include "cuda/parallel/partitioned_engine.h"

namespace pd {

bool cuda_device_available(std::string* why) {
  int count = 0;
  const cudaError_t err = cudaGetDeviceCount(&count);
  if (err != cudaSuccess || count == 0) {
    if (why) *why = err != cudaSuccess ? cudaGetErrorString(err) : "no CUDA device found";
    cudaGetLastError();  // clear the sticky error of a failed probe
    return false;
  }
  return true;
}

size_t cuda_free_bytes() {
  if (!cuda_device_available()) return 0;
  size_t free_b = 0, total_b = 0;
  if (cudaMemGetInfo(&free_b, &total_b) != cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  return free_b;
}

void profiler_range_push(const char* name) {
  nvtxRangePushA(name);
}
void profiler_range_pop() {
  nvtxRangePop();
}

std::unique_ptr<Engine> make_cuda_engine(const SimulationInput& in) {
  std::string why;
  if (!cuda_device_available(&why)) throw std::runtime_error("CUDA backend unavailable: " + why);
  // A partitioned run: each rank of a host takes the next GPU (several ranks share one when the
  // host has fewer GPUs than ranks).
  const std::shared_ptr<Comm> world = world_comm();
  int device = 0, devices = 1;
  cuda_check(cudaGetDeviceCount(&devices), "cudaGetDeviceCount");
  if (world) device = world->local_rank() % devices;
  cuda_check(cudaSetDevice(device), "cudaSetDevice");
  cudaDeviceProp prop{};
  cuda_check(cudaGetDeviceProperties(&prop, device), "cudaGetDeviceProperties");
  int driver = 0;
  cudaDriverGetVersion(&driver);
  const std::string name = std::string(prop.name) + " (sm_" + std::to_string(prop.major) +
                           std::to_string(prop.minor) + ", " + std::to_string(prop.multiProcessorCount) +
                           " SMs, driver API " + std::to_string(driver / 1000) + "." +
                           std::to_string(driver % 1000 / 10) + ")";
  if (world) return make_partitioned_engine<CudaExec>(in, world, name);
  return std::make_unique<EngineImpl<CudaExec>>(in, name);
}

}  // namespace pd
