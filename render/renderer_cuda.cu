// The CUDA renderer: the shared pixel kernel, one pixel per thread.
#include "cuda/engine/engine.h"
#include "cuda/exec_cuda.cuh"
#include "render/renderer_impl.h"

namespace pd {

std::unique_ptr<Renderer> make_cuda_renderer() {
  std::string why;
  if (!cuda_device_available(&why)) throw std::runtime_error("CUDA renderer unavailable: " + why);
  int device = 0;
  cudaDeviceProp prop{};
  cuda_check(cudaGetDevice(&device), "cudaGetDevice");
  cuda_check(cudaGetDeviceProperties(&prop, device), "cudaGetDeviceProperties");
  return std::make_unique<RendererImpl<CudaExec>>(
      std::string(prop.name) + " (sm_" + std::to_string(prop.major) + std::to_string(prop.minor) + ")");
}

}  // namespace pd
