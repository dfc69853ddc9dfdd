#include "host/app/backend_choice.h"

#include <stdexcept>

namespace pd {

Backend choose_backend(const std::string& name, std::string* note) {
  std::string why;
  if (name == "cpu") return Backend::kCpu;
  if (name == "cuda") {
    if (!cuda_device_available(&why)) throw std::runtime_error("--backend cuda: " + why);
    return Backend::kCuda;
  }
  if (name == "auto") {
    if (cuda_device_available(&why)) return Backend::kCuda;
    if (note) *note = "no GPU (" + why + "): running the CPU-reference backend";
    return Backend::kCpu;
  }
  throw std::invalid_argument("--backend: unknown backend '" + name + "' (allowed: auto, cpu, cuda)");
}

}  // namespace pd
