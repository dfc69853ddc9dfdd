// Linked instead of cuda/engine_cuda.cu when the build has no CUDA compiler.
#include <stdexcept>

#include "cuda/engine/engine.h"

namespace pd {

bool cuda_device_available(std::string* why) {
  if (why) *why = "this build has no CUDA support (configure with a CUDA compiler, preset 'cuda')";
  return false;
}

size_t cuda_free_bytes() {
  return 0;
}

void profiler_range_push(const char*) {}
void profiler_range_pop() {}

std::unique_ptr<Engine> make_cuda_engine(const SimulationInput&) {
  throw std::runtime_error("CUDA backend unavailable: this build has no CUDA support");
}

}  // namespace pd
