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
#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#define CK(x)                                                                          \
  do {                                                                                 \
    cudaError_t e = (x);                                                               \
    if (e != cudaSuccess) {                                                            \
      std::fprintf(stderr, "%s: %s (line %d)\n", #x, cudaGetErrorString(e), __LINE__); \
      std::exit(1);                                                                    \
    }                                                                                  \
  } while (0)

constexpr int W = 32;  // slice width

struct Families {
  int n = 0;
  std::vector<int> count;
  std::vector<long long> slice_off;  // per slice
  std::vector<int> neighbor;         // sliced ELL
  std::vector<uint16_t> surface;     // per slot
  long long bonds = 0, slots = 0;
  long long slot(int i, int k) const { return slice_off[i / W] + (long long)k * W + i % W; }
};

static Families build(const std::vector<float>& pos, float delta) {
  Families f;
  const int n = int(pos.size() / 3);
  f.n = n;
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], pos[3 * i + a]), hi[a] = std::max(hi[a], pos[3 * i + a]);
  int dim[3];
  for (int a = 0; a < 3; ++a) dim[a] = std::max(1, int((hi[a] - lo[a]) / delta) + 1);
  std::vector<int> cell_of(n), start(size_t(dim[0]) * dim[1] * dim[2] + 1, 0);
  auto cell = [&](int i, int a) { return std::min(dim[a] - 1, int((pos[3 * i + a] - lo[a]) / delta)); };
  for (int i = 0; i < n; ++i)
    cell_of[i] = (cell(i, 2) * dim[1] + cell(i, 1)) * dim[0] + cell(i, 0), ++start[cell_of[i] + 1];
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<int> items(n), fill(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) items[fill[cell_of[i]]++] = i;
  std::vector<std::vector<int>> fam(n);
  const float d2 = delta * delta;
  for (int i = 0; i < n; ++i) {
    const int cx = cell(i, 0), cy = cell(i, 1), cz = cell(i, 2);
    for (int z = std::max(0, cz - 1); z <= std::min(dim[2] - 1, cz + 1); ++z)
      for (int y = std::max(0, cy - 1); y <= std::min(dim[1] - 1, cy + 1); ++y)
        for (int x = std::max(0, cx - 1); x <= std::min(dim[0] - 1, cx + 1); ++x) {
          const int c = (z * dim[1] + y) * dim[0] + x;
          for (int q = start[c]; q < start[c + 1]; ++q) {
            const int j = items[q];
            if (j == i) continue;
            float r2 = 0;
            for (int a = 0; a < 3; ++a)
              r2 += (pos[3 * j + a] - pos[3 * i + a]) * (pos[3 * j + a] - pos[3 * i + a]);
            if (r2 <= d2) fam[i].push_back(j);
          }
        }
    std::sort(fam[i].begin(), fam[i].end());
  }
  f.count.resize(n);
  const int slices = (n + W - 1) / W;
  f.slice_off.resize(slices);
  long long off = 0;
  for (int s = 0; s < slices; ++s) {
    int width = 0;
    for (int i = s * W; i < std::min(n, s * W + W); ++i) width = std::max(width, int(fam[i].size()));
    f.slice_off[s] = off;
    off += (long long)width * W;
  }
  f.slots = off;
  f.neighbor.assign(off, -1);
  f.surface.assign(off, 0);
  std::mt19937 rng(7);
  for (int i = 0; i < n; ++i) {
    f.count[i] = int(fam[i].size());
    f.bonds += f.count[i];
    for (int k = 0; k < f.count[i]; ++k) {
      f.neighbor[f.slot(i, k)] = fam[i][k];
      f.surface[f.slot(i, k)] = uint16_t(32768 + rng() % 4096);  // a factor near 1
    }
  }
  return f;
}

__device__ __forceinline__ float factor(uint32_t s) {
  return float(s) * (1.0f / 32768.0f);
}

struct Bond {
  float3 f;
  float smin, nearest;
};

__device__ __forceinline__ void visit(float4 ri, float4 ui, float4 rj, float4 uj, uint32_t surf,
                                      float horizon, float spacing, Bond& acc) {
  const float xx = rj.x - ri.x, xy = rj.y - ri.y, xz = rj.z - ri.z;
  const float ex = uj.x - ui.x, ey = uj.y - ui.y, ez = uj.z - ui.z;
  const float yx = xx + ex, yy = xy + ey, yz = xz + ez;
  const float r02 = xx * xx + xy * xy + xz * xz, r2 = yx * yx + yy * yy + yz * yz;
  const float inv_r0 = rsqrtf(r02), r0 = r02 * inv_r0;
  const float inv_r = r2 >= 1.17549435e-38f ? rsqrtf(r2) : 0.f, r = r2 * inv_r;
  const float e = __fdividef(2.f * (xx * ex + xy * ey + xz * ez) + (ex * ex + ey * ey + ez * ez), r + r0);
  const float s = e * inv_r0;
  const float half = 0.5f * spacing;
  const float beta = r0 <= horizon - half ? 1.f : __fdividef(horizon + half - r0, spacing);
  const float w = beta * rj.w * factor(surf);
  acc.nearest = fmaxf(acc.nearest, s);
  acc.smin = fminf(s, acc.smin);
  const float c = s * w * inv_r;
  acc.f.x += c * yx;
  acc.f.y += c * yy;
  acc.f.z += c * yz;
}

template <int T>
__device__ __forceinline__ float team_sum(float v) {
  for (int o = T / 2; o > 0; o /= 2) v += __shfl_xor_sync(0xffffffffu, v, o, T);
  return v;
}
template <int T>
__device__ __forceinline__ float team_min(float v) {
  for (int o = T / 2; o > 0; o /= 2) v = fminf(v, __shfl_xor_sync(0xffffffffu, v, o, T));
  return v;
}
template <int T>
__device__ __forceinline__ float team_max(float v) {
  for (int o = T / 2; o > 0; o /= 2) v = fmaxf(v, __shfl_xor_sync(0xffffffffu, v, o, T));
  return v;
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

template <int T>
__device__ __forceinline__ void finish(int i, Bond acc, const View& v, int lane) {
  acc.f.x = team_sum<T>(acc.f.x);
  acc.f.y = team_sum<T>(acc.f.y);
  acc.f.z = team_sum<T>(acc.f.z);
  acc.smin = team_min<T>(acc.smin);
  acc.nearest = team_max<T>(acc.nearest);
  if (lane == 0) v.force[i] = make_float4(acc.f.x, acc.f.y, acc.f.z, acc.smin + 0.f * acc.nearest);
}

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
  finish<T>(i, acc, v, lane);
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
  finish<T>(i, acc, v, lane);
}

template <class F>
static double time_ms(F launch, int reps) {
  cudaEvent_t a, b;
  CK(cudaEventCreate(&a));
  CK(cudaEventCreate(&b));
  for (int r = 0; r < 5; ++r) launch();
  CK(cudaEventRecord(a));
  for (int r = 0; r < reps; ++r) launch();
  CK(cudaEventRecord(b));
  CK(cudaEventSynchronize(b));
  float ms = 0;
  CK(cudaEventElapsedTime(&ms, a, b));
  CK(cudaGetLastError());
  return ms / reps;
}

template <class X>
static X* up(const std::vector<X>& h) {
  X* d = nullptr;
  CK(cudaMalloc(&d, sizeof(X) * std::max<size_t>(1, h.size())));
  CK(cudaMemcpy(d, h.data(), sizeof(X) * h.size(), cudaMemcpyHostToDevice));
  return d;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: tiled_partners points.ply DELTA LAMBDA | tiled_partners --lattice N\n");
    return 2;
  }
  std::vector<float> pos;
  float delta = 0, spacing = 0;
  std::string what;
  if (std::string(argv[1]) == "--lattice") {
    const int m = std::atoi(argv[2]);
    spacing = 1e-3f;
    delta = 3.015f * spacing;
    for (int z = 0; z < m; ++z)
      for (int y = 0; y < m; ++y)
        for (int x = 0; x < m; ++x) pos.insert(pos.end(), {x * spacing, y * spacing, z * spacing});
    what = "explicit lattice " + std::to_string(m) + "^3";
  } else {
    // A frame's points_NNNNN.ply: binary, x y z first, every property 4 bytes.
    FILE* fp = std::fopen(argv[1], "rb");
    if (!fp) return 2;
    char line[256];
    long vertices = 0;
    int properties = 0;
    while (std::fgets(line, sizeof line, fp) && std::strncmp(line, "end_header", 10) != 0) {
      std::sscanf(line, "element vertex %ld", &vertices);
      if (std::strncmp(line, "property", 8) == 0) ++properties;
    }
    std::vector<float> row(static_cast<size_t>(properties));
    for (long v = 0; v < vertices; ++v) {
      if (std::fread(row.data(), 4, row.size(), fp) != row.size()) return 2;
      pos.insert(pos.end(), {row[0], row[1], row[2]});
    }
    std::fclose(fp);
    delta = std::atof(argv[2]);
    spacing = std::atof(argv[3]);
    what = argv[1];
  }
  const auto t0 = std::chrono::steady_clock::now();
  Families f = build(pos, delta);
  const int n = f.n;
  std::printf("%s: %d particles, %lld bonds (%.1f each), families %.1f s\n", what.c_str(), n, f.bonds,
              double(f.bonds) / n,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  std::vector<float4> rest(n), disp(n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1e-6f, 1e-6f);
  for (int i = 0; i < n; ++i) {
    rest[i] = make_float4(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], spacing * spacing * spacing);
    disp[i] = make_float4(u(rng), u(rng), u(rng), 1e-3f);
  }
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
