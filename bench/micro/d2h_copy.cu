// Device-to-host copies of a frame's size (25 MiB, the vase's per-frame read-back at Levine's size):
// pageable cudaMemcpy against a pinned, double-buffered staging copy (chunks of 1, 4, 8 MiB), and
// pageable into fresh pages. A measurement behind bench/NOTES.md ("Frames read back through pinned
// staging"); not part of the build. Build and run on a GPU machine:
//   nvcc -O2 -arch=sm_90 -o d2h_copy bench/micro/d2h_copy.cu && ./d2h_copy
#include <cuda_runtime.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>
static double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
int main() {
  const size_t bytes = 25u << 20;
  void* dev;
  cudaMalloc(&dev, bytes);
  cudaMemset(dev, 1, bytes);
  std::vector<char> host(bytes);
  for (size_t chunk : {size_t(1) << 20, size_t(4) << 20, size_t(8) << 20}) {
    char* stage[2];
    cudaEvent_t ev[2];
    for (int b = 0; b < 2; ++b) {
      cudaHostAlloc((void**)&stage[b], chunk, 0);
      cudaEventCreateWithFlags(&ev[b], cudaEventDisableTiming);
    }
    for (int round = 0; round < 3; ++round) {
      double t0 = now();
      for (int r = 0; r < 20; ++r) cudaMemcpy(host.data(), dev, bytes, cudaMemcpyDeviceToHost);
      double t1 = now();
      for (int r = 0; r < 20; ++r) {
        size_t pending[2] = {0, 0}, at[2] = {0, 0};
        int k = 0;
        for (size_t off = 0; off < bytes; off += chunk, ++k) {
          int b = k % 2;
          if (pending[b]) {
            cudaEventSynchronize(ev[b]);
            std::memcpy(host.data() + at[b], stage[b], pending[b]);
          }
          size_t n = std::min(chunk, bytes - off);
          cudaMemcpyAsync(stage[b], (char*)dev + off, n, cudaMemcpyDeviceToHost, 0);
          cudaEventRecord(ev[b], 0);
          pending[b] = n;
          at[b] = off;
        }
        for (int b = 0; b < 2; ++b) {
          int bb = (k + b) % 2;
          if (pending[bb]) {
            cudaEventSynchronize(ev[bb]);
            std::memcpy(host.data() + at[bb], stage[bb], pending[bb]);
          }
        }
      }
      double t2 = now();
      std::vector<char> fresh(bytes);
      double t3 = now();
      cudaMemcpy(fresh.data(), dev, bytes, cudaMemcpyDeviceToHost);
      double t4 = now();
      std::printf(
          "chunk %zu MiB round %d: pageable %.2f ms (%.1f GB/s), staged %.2f ms (%.1f GB/s), pageable into "
          "fresh pages %.2f ms\n",
          chunk >> 20, round, (t1 - t0) / 20 * 1e3, bytes / ((t1 - t0) / 20) / 1e9, (t2 - t1) / 20 * 1e3,
          bytes / ((t2 - t1) / 20) / 1e9, (t4 - t3) * 1e3);
    }
  }
  return 0;
}
