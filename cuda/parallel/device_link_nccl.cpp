// The device link over NCCL: one communicator over the world's ranks, its unique id broadcast
// from rank 0 over MPI; each exchange is one NCCL group of point-to-point sends and receives.
#include <cuda_runtime.h>
#include <nccl.h>

#include <stdexcept>
#include <string>

#include "cuda/parallel/device_link.h"

namespace pd {

namespace {

void check(ncclResult_t err, const char* what) {
  if (err == ncclSuccess) return;
  throw std::runtime_error(std::string("NCCL ") + what + " failed: " + ncclGetErrorString(err) +
                           " (set PERIFRAC_HALO=host to exchange the halo through host memory instead)");
}

class NcclLink final : public DeviceLink {
 public:
  explicit NcclLink(Comm& world) {
    ncclUniqueId id{};
    if (world.rank() == 0) check(ncclGetUniqueId(&id), "ncclGetUniqueId");
    world.broadcast(&id, sizeof(id), 0);
    check(ncclCommInitRank(&comm_, world.size(), id, world.rank()), "ncclCommInitRank");
  }
  ~NcclLink() override { ncclCommDestroy(comm_); }

  void exchange(const std::vector<Transfer>& send, const std::vector<Transfer>& recv, void* stream) override {
    const cudaStream_t s = static_cast<cudaStream_t>(stream);
    check(ncclGroupStart(), "ncclGroupStart");
    for (const Transfer& t : send)
      if (t.bytes > 0) check(ncclSend(t.data, t.bytes, ncclChar, t.peer, comm_, s), "ncclSend");
    for (const Transfer& t : recv)
      if (t.bytes > 0) check(ncclRecv(t.data, t.bytes, ncclChar, t.peer, comm_, s), "ncclRecv");
    check(ncclGroupEnd(), "ncclGroupEnd");
  }

 private:
  ncclComm_t comm_ = nullptr;
};

}  // namespace

bool device_link_available() {
  return true;
}

std::unique_ptr<DeviceLink> make_device_link(Comm& world) {
  return std::make_unique<NcclLink>(world);
}

}  // namespace pd
