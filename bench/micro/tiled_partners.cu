// Explicit families' bond-based force loop (the screened pass's sums: PMB stretch, partial volume,
// a 16-bit surface factor a slot) in two forms: each bond's partner records gathered from global
// memory with the next index loaded ahead (the engine's form, for_each_intact_listed_bond), against
// a block's partners staged once in shared memory and its bonds read through 16-bit indices into
// them (issue 27 item 2, "offsets from a block base"), teams of 1 to 8 lanes each. Both forms sum
// the same numbers in the same order, so the forces must agree bit for bit (checked). A measurement
// behind bench/NOTES.md ("Partners staged in shared memory"); not part of the build. On a GPU machine:
//   nvcc -O3 -std=c++17 -arch=sm_90 -o tiled_partners bench/micro/tiled_partners.cu
//   ./tiled_partners RUN/points_00000.ply DELTA LAMBDA   (a run's frame 0: the vase at --scale 4.27
//                                                        has delta 0.003345, lambda 0.0008363)
//   ./tiled_partners --lattice 100                       (1M particles, delta 3.015 lambda)
#include <chrono>

#include "micro_families.h"

__device__ __forceinline__ float factor(uint32_t s) {
  return float(s) * (1.0f / 32768.0f);
}

__device__ __forceinline__ void visit(float4 ri, float4 ui, float4 rj, float4 uj, uint32_t surf,
                                      float horizon, float spacing, Bond& acc) {
  const Stretch b = stretch(ri, ui, rj, uj);
  accumulate(b, partial_volume(b.r0, horizon, spacing) * rj.w * factor(surf), acc);
}

struct View {
  int n;
  const int* count;
  const long long* slice_off;
  const int* neighbor;
  const uint16_t* local;
  const uint16_t* surface;
  const float4* rest;
  const float4* disp;
  const int* tile_first;  // per block
  const int* tile;        // global indices
  float4* force;
  float horizon, spacing;
};

// The engine's form: partners gathered from global memory, the next index loaded ahead.
template <int T>
__global__ void __launch_bounds__(256) global_kernel(View v) {
  const int t = (blockIdx.x * blockDim.x + threadIdx.x) / T, lane = threadIdx.x % T;
  if (t >= v.n) return;
  const int i = t;
  const float4 ri = v.rest[i], ui = v.disp[i];
  const int count = v.count[i];
  const long long first = v.slice_off[i / W] + i % W;
  Bond acc{{0, 0, 0}, INFINITY, -INFINITY};
  int next = 0;
  uint32_t next_s = 0;
  if (lane < count)
    next = __ldcs(v.neighbor + first + (long long)lane * W),
    next_s = __ldcs(v.surface + first + (long long)lane * W);
  for (int k = lane; k < count; k += T) {
    const int j = next;
    const uint32_t s = next_s;
    if (k + T < count) {
      const long long ns = first + (long long)(k + T) * W;
      next = __ldcs(v.neighbor + ns);
      next_s = __ldcs(v.surface + ns);
    }
    if (j < 0) continue;
    visit(ri, ui, v.rest[j], v.disp[j], s, v.horizon, v.spacing, acc);
  }
  finish<T>(i, acc, v.force, lane);
}

// Staged: the block's partners' records in shared memory, bonds by 16-bit local index.
template <int T>
__global__ void __launch_bounds__(256) tiled_kernel(View v) {
  extern __shared__ float4 sm[];
  const int P = 256 / T;
  const int b0 = v.tile_first[blockIdx.x], tn = v.tile_first[blockIdx.x + 1] - b0;
  float4* sr = sm;
  float4* sd = sm + tn;
  for (int q = threadIdx.x; q < tn; q += blockDim.x) {
    const int j = v.tile[b0 + q];
    sr[q] = v.rest[j];
    sd[q] = v.disp[j];
  }
  __syncthreads();
  const int i = blockIdx.x * P + threadIdx.x / T, lane = threadIdx.x % T;
  if (i >= v.n) return;
  const float4 ri = v.rest[i], ui = v.disp[i];
  const int count = v.count[i];
  const long long first = v.slice_off[i / W] + i % W;
  Bond acc{{0, 0, 0}, INFINITY, -INFINITY};
  uint32_t next = 0, next_s = 0;
  if (lane < count)
    next = __ldcs(v.local + first + (long long)lane * W),
    next_s = __ldcs(v.surface + first + (long long)lane * W);
  for (int k = lane; k < count; k += T) {
    const uint32_t j = next;
    const uint32_t s = next_s;
    if (k + T < count) {
      const long long ns = first + (long long)(k + T) * W;
      next = __ldcs(v.local + ns);
      next_s = __ldcs(v.surface + ns);
    }
    if (j & 0x8000u) continue;
    visit(ri, ui, sr[j], sd[j], s, v.horizon, v.spacing, acc);
  }
  finish<T>(i, acc, v.force, lane);
}

int main(int argc, char** argv) {
  Input in;
  if (!read_input(argc, argv, in)) return 2;
  const std::vector<float>& pos = in.pos;
  const float delta = in.delta, spacing = in.spacing;
  const std::string& what = in.what;
  const auto t0 = std::chrono::steady_clock::now();
  Families f = build(pos, delta, 32768, 4096);  // factors in [1, 1.125), steps of 2^-15
  const int n = f.n;
  std::printf("%s: %d particles, %lld bonds (%.1f each), families %.1f s\n", what.c_str(), n, f.bonds,
              double(f.bonds) / n,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  std::vector<float4> rest, disp;
  particle_records(pos, spacing, rest, disp);
  View v{};
  v.n = n;
  v.horizon = delta;
  v.spacing = spacing;
  v.count = up(f.count);
  v.slice_off = up(f.slice_off);
  v.neighbor = up(f.neighbor);
  v.surface = up(f.surface);
  v.rest = up(rest);
  v.disp = up(disp);
  float4* force = nullptr;
  CK(cudaMalloc(&force, sizeof(float4) * n));
  v.force = force;
  std::vector<float4> got(n);
  std::vector<std::vector<float4>> refs(9, std::vector<float4>());
  auto report = [&](const char* name, double ms) {
    std::printf("  %-34s %8.4f ms  %.3e bond-updates/s\n", name, ms, double(f.bonds) / (ms * 1e-3));
  };
  // global forms
  auto run_global = [&](auto tag) {
    constexpr int T = decltype(tag)::value;
    const int blocks = int((long long)n * T / 256 + 1);
    const double ms = time_ms([&] { global_kernel<T><<<blocks, 256>>>(v); }, 50);
    char name[64];
    std::snprintf(name, sizeof name, "global, %d lane(s)", T);
    report(name, ms);
    refs[T].resize(n);
    CK(cudaMemcpy(refs[T].data(), force, sizeof(float4) * n, cudaMemcpyDeviceToHost));
  };
  run_global(std::integral_constant<int, 1>{});
  run_global(std::integral_constant<int, 2>{});
  run_global(std::integral_constant<int, 4>{});
  run_global(std::integral_constant<int, 8>{});
  // tiled forms
  auto run_tiled = [&](auto tag) {
    constexpr int T = decltype(tag)::value;
    constexpr int P = 256 / T;
    const int blocks = (n + P - 1) / P;
    std::vector<int> tile_first(blocks + 1, 0), tile;
    std::vector<uint16_t> local(f.slots, 0x8000u);
    int most = 0;
    long long loads = 0;
    for (int b = 0; b < blocks; ++b) {
      std::vector<int> u;
      for (int i = b * P; i < std::min(n, b * P + P); ++i)
        for (int k = 0; k < f.count[i]; ++k) u.push_back(f.neighbor[f.slot(i, k)]);
      std::sort(u.begin(), u.end());
      u.erase(std::unique(u.begin(), u.end()), u.end());
      if (u.size() > 32767) {
        std::printf("  tiled %d: block %d has %zu partners, too many\n", T, b, u.size());
        return;
      }
      for (int i = b * P; i < std::min(n, b * P + P); ++i)
        for (int k = 0; k < f.count[i]; ++k)
          local[f.slot(i, k)] =
              uint16_t(std::lower_bound(u.begin(), u.end(), f.neighbor[f.slot(i, k)]) - u.begin());
      tile_first[b] = int(tile.size());
      tile.insert(tile.end(), u.begin(), u.end());
      most = std::max(most, int(u.size()));
      loads += long(u.size());
    }
    tile_first[blocks] = int(tile.size());
    View t = v;
    t.tile_first = up(tile_first);
    t.tile = up(tile);
    t.local = up(local);
    const size_t shared = size_t(most) * 32;
    CK(cudaFuncSetAttribute(tiled_kernel<T>, cudaFuncAttributeMaxDynamicSharedMemorySize, int(shared)));
    int per_sm = 0;
    CK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, tiled_kernel<T>, 256, shared));
    const double ms = time_ms([&] { tiled_kernel<T><<<blocks, 256, shared>>>(t); }, 50);
    char name[96];
    std::snprintf(name, sizeof name, "tiled, %d lane(s), %d/block", T, P);
    report(name, ms);
    std::printf(
        "      tile: mean %.0f, most %d partners (%zu B shared), %d blocks/SM, %.1f bonds per staged "
        "record\n",
        double(loads) / blocks, most, shared, per_sm, double(f.bonds) / double(loads));
    CK(cudaMemcpy(got.data(), force, sizeof(float4) * n, cudaMemcpyDeviceToHost));
    const std::vector<float4>& ref = refs[T];
    long long diff = 0;
    double worst = 0;
    for (int i = 0; i < n; ++i) {
      if (std::memcmp(&got[i], &ref[i], sizeof(float4)) != 0) ++diff;
      const double d = std::fabs(double(got[i].x) - ref[i].x) / (std::fabs(double(ref[i].x)) + 1e-30);
      worst = std::max(worst, d);
    }
    std::printf("      against global, same lanes: %lld particles differ in bits, largest relative %.2e\n",
                diff, worst);
    cudaFree((void*)t.tile_first);
    cudaFree((void*)t.tile);
    cudaFree((void*)t.local);
  };
  run_tiled(std::integral_constant<int, 1>{});
  run_tiled(std::integral_constant<int, 2>{});
  run_tiled(std::integral_constant<int, 4>{});
  run_tiled(std::integral_constant<int, 8>{});
  return 0;
}
