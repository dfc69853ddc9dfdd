#include "cuda/engine/engine.h"

namespace pd {

const char* backend_name(Backend b) {
  return b == Backend::kCuda ? "cuda" : "cpu";
}

std::unique_ptr<Engine> make_engine(Backend b, const SimulationInput& in) {
  return b == Backend::kCuda ? make_cuda_engine(in) : make_cpu_engine(in);
}

}  // namespace pd
