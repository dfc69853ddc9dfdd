// Explicit families' bond-based force loop (the screened pass's sums: PMB stretch, partial volume,
// a surface factor a slot; the engine's loop shape, the next index loaded ahead, teams of 1 and 4
// lanes) with the bond's weight taken in different forms: the engine's (the partial volume of the
// partner computed at every bond from |xi|, times the 16-bit factor in steps of 2^-12) against the
// partial volume folded into the stored factor at set-up (16-bit steps, half precision, float).
// A measurement behind bench/NOTES.md ("The partial volume folded into the listed bond's factor");
// not part of the build. On a GPU machine:
//   nvcc -O3 -std=c++17 -arch=sm_90 -o listed_weights bench/micro/listed_weights.cu
//   ./listed_weights RUN/points_00000.ply DELTA LAMBDA   (a run's frame 0: the vase at --scale 4.27
//                                                        has delta 0.003345, lambda 0.0008363)
//   ./listed_weights --lattice 100                       (1M particles, delta 3.015 lambda)
#include <cuda_fp16.h>

#include "micro_families.h"

// How a bond's weight beyond the partner's volume is stored and taken.
enum Form : int {
  kComputed = 0,  // the engine's: beta(|xi|) at every bond, times the 16-bit factor
  kFolded16 = 1,  // beta g in one 16-bit word, steps of 2^-12
  kFoldedHalf = 2,
  kFoldedFloat = 3,
};

template <class S>
__device__ __forceinline__ float stored_value(S s);
template <>
__device__ __forceinline__ float stored_value(uint32_t s) {
  return float(s) * (1.0f / 4096.0f);
}
template <>
__device__ __forceinline__ float stored_value(__half s) {
  return __half2float(s);
}
template <>
__device__ __forceinline__ float stored_value(float s) {
  return s;
}

template <int kForm, class S>
__device__ __forceinline__ void visit(float4 ri, float4 ui, float4 rj, float4 uj, S surf, float horizon,
                                      float spacing, Bond& acc) {
  const Stretch b = stretch(ri, ui, rj, uj);
  if constexpr (kForm == kComputed)
    accumulate(b, partial_volume(b.r0, horizon, spacing) * rj.w * stored_value(surf), acc);
  else
    accumulate(b, rj.w * stored_value(surf), acc);
}

template <class S>
struct View {
  int n;
  const int* count;
  const long long* slice_off;
  const int* neighbor;
  const S* surface;  // per slot
  const float4* rest;
  const float4* disp;
  float4* force;
  float horizon, spacing;
};

// The engine's loop (for_each_intact_listed_bond): the next index and factor loaded ahead; 6 blocks
// an SM (40 registers), as the engine bounds its listed bond-based passes.
template <int T, int kForm, class S, class L>
__global__ void __launch_bounds__(256, 6) listed_kernel(View<S> v) {
  const int i = (blockIdx.x * blockDim.x + threadIdx.x) / T, lane = threadIdx.x % T;
  if (i >= v.n) return;
  const float4 ri = v.rest[i], ui = v.disp[i];
  const int count = v.count[i];
  const long long first = v.slice_off[i / W] + i % W;
  Bond acc{{0, 0, 0}, INFINITY, -INFINITY};
  int next = 0;
  L next_s{};
  if (lane < count)
    next = __ldcs(v.neighbor + first + (long long)lane * W),
    next_s = L(__ldcs(v.surface + first + (long long)lane * W));
  for (int k = lane; k < count; k += T) {
    const int j = next;
    const L s = next_s;
    if (k + T < count) {
      const long long ns = first + (long long)(k + T) * W;
      next = __ldcs(v.neighbor + ns);
      next_s = L(__ldcs(v.surface + ns));
    }
    if (j < 0) continue;
    visit<kForm>(ri, ui, v.rest[j], v.disp[j], s, v.horizon, v.spacing, acc);
  }
  finish<T>(i, acc, v.force, lane);
}

int main(int argc, char** argv) {
  Input in;
  if (!read_input(argc, argv, in)) return 2;
  const std::vector<float>& pos = in.pos;
  const float delta = in.delta, spacing = in.spacing;
  const std::string& what = in.what;
  Families f = build(pos, delta, 4096 - 256, 512);  // factors in [0.9375, 1.0625), steps of 2^-12
  const int n = f.n;
  std::printf("%s: %d particles, %lld bonds (%.1f each)\n", what.c_str(), n, f.bonds, double(f.bonds) / n);
  std::vector<float4> rest, disp;
  particle_records(pos, spacing, rest, disp);
  // The folded factors: beta(|xi|) g per slot, from the same reference vector the kernel forms.
  std::vector<uint16_t> folded16(f.slots, 0);
  std::vector<__half> folded_half(f.slots, __float2half(0.f));
  std::vector<float> folded_float(f.slots, 0.f);
  long long partial = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < f.count[i]; ++k) {
      const long long q = f.slot(i, k);
      const int j = f.neighbor[q];
      const float xx = rest[j].x - rest[i].x, xy = rest[j].y - rest[i].y, xz = rest[j].z - rest[i].z;
      const float r0 = std::sqrt(xx * xx + xy * xy + xz * xz);
      const float half = 0.5f * spacing;
      const float beta = r0 <= delta - half ? 1.f : (delta + half - r0) / spacing;
      partial += beta < 1.f;
      const float g = beta * float(f.surface[q]) / 4096.f;
      folded16[q] = uint16_t(std::lround(g * 4096.f));
      folded_half[q] = __float2half(g);
      folded_float[q] = g;
    }
  std::printf("  bonds with a partial volume: %.1f%%\n", 100.0 * double(partial) / double(f.bonds));
  float4* force = nullptr;
  CK(cudaMalloc(&force, sizeof(float4) * n));
  auto base_view = [&](auto* surface) {
    View<std::remove_const_t<std::remove_pointer_t<decltype(surface)>>> v{};
    v.n = n;
    v.horizon = delta;
    v.spacing = spacing;
    v.count = up(f.count);
    v.slice_off = up(f.slice_off);
    v.neighbor = up(f.neighbor);
    v.surface = surface;
    v.rest = up(rest);
    v.disp = up(disp);
    v.force = force;
    return v;
  };
  const View<uint16_t> v_computed = base_view(up(f.surface));
  const View<uint16_t> v_folded16 = base_view(up(folded16));
  const View<__half> v_half = base_view(up(folded_half));
  const View<float> v_float = base_view(up(folded_float));
  std::vector<float4> ref(n), got(n);
  auto compare = [&](const char* name) {
    CK(cudaMemcpy(got.data(), force, sizeof(float4) * n, cudaMemcpyDeviceToHost));
    double worst = 0, sum_ref = 0, sum_err = 0;
    for (int i = 0; i < n; ++i) {
      const double fr =
          std::sqrt(double(ref[i].x) * ref[i].x + double(ref[i].y) * ref[i].y + double(ref[i].z) * ref[i].z);
      const double d = std::sqrt(double(got[i].x - ref[i].x) * (got[i].x - ref[i].x) +
                                 double(got[i].y - ref[i].y) * (got[i].y - ref[i].y) +
                                 double(got[i].z - ref[i].z) * (got[i].z - ref[i].z));
      sum_ref += fr, sum_err += d;
      worst = std::max(worst, d / (fr + 1e-30));
    }
    std::printf("      %s against computed: force error |df| / |f| summed %.2e, largest %.2e\n", name,
                sum_err / sum_ref, worst);
  };
  auto run = [&](auto lanes, int round) {
    constexpr int T = decltype(lanes)::value;
    const int blocks = int((long long)n * T / 256 + 1);
    auto go = [&](const char* name, auto kernel, const auto& view, bool check) {
      const double ms = time_ms([&] { kernel<<<blocks, 256>>>(view); }, 100);
      std::printf("  round %d, %d lane(s), %-24s %8.4f ms  %.4e bond-updates/s\n", round, T, name, ms,
                  double(f.bonds) / (ms * 1e-3));
      if (check) compare(name);
    };
    go("computed (engine)", listed_kernel<T, kComputed, uint16_t, uint32_t>, v_computed, false);
    CK(cudaMemcpy(ref.data(), force, sizeof(float4) * n, cudaMemcpyDeviceToHost));
    go("folded, 16-bit steps", listed_kernel<T, kFolded16, uint16_t, uint32_t>, v_folded16, round == 1);
    go("folded, half", listed_kernel<T, kFoldedHalf, __half, __half>, v_half, round == 1);
    go("folded, float", listed_kernel<T, kFoldedFloat, float, float>, v_float, round == 1);
  };
  for (int round = 1; round <= 2; ++round) {
    run(std::integral_constant<int, 1>{}, round);
    run(std::integral_constant<int, 2>{}, round);
    run(std::integral_constant<int, 4>{}, round);
  }
  return 0;
}
