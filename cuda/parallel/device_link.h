// Messages between the GPUs of a partitioned run (NCCL): grouped sends and receives of device
// buffers, queued on a CUDA stream, so the halo never passes through host memory and the host
// never waits for it. Built where NCCL is found (device_link_nccl.cpp); otherwise there is no
// link and the halo is staged through host memory over MPI (cuda/parallel/halo.h).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "cuda/parallel/comm.h"

namespace pd {

class DeviceLink {
 public:
  struct Transfer {
    int peer = 0;
    void* data = nullptr;  // device memory
    size_t bytes = 0;
  };
  virtual ~DeviceLink() = default;
  // One group of sends and receives, queued on `stream` (a cudaStream_t): work queued there
  // afterwards sees the received bytes. The messages of one peer pair up in the order given.
  virtual void exchange(const std::vector<Transfer>& send, const std::vector<Transfer>& recv,
                        void* stream) = 0;
};

// Whether this build can link GPUs (NCCL found).
bool device_link_available();

// A link over every rank of `world`, each on its current CUDA device. Collective: every rank
// calls it together. Throws where NCCL cannot join the ranks.
std::unique_ptr<DeviceLink> make_device_link(Comm& world);

}  // namespace pd
