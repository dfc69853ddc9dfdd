// A build without NCCL: no device link; the halo of a partitioned GPU run goes through host memory.
#include <stdexcept>

#include "cuda/parallel/device_link.h"

namespace pd {

bool device_link_available() {
  return false;
}

std::unique_ptr<DeviceLink> make_device_link(Comm&) {
  throw std::logic_error("this build has no NCCL");
}

}  // namespace pd
