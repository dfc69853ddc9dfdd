// One device-to-host copy of a read-back that overlaps later launches (CudaExec::read_back,
// CpuExec::read_back; Engine::read_frame).
#pragma once

#include <cstddef>

namespace pd {

struct HostCopy {
  void* dst;  // host memory from the backend's allocate_host
  const void* src;
  size_t bytes;
};

}  // namespace pd
