// Shared by the micro-benchmarks of bench/micro/ (measurements behind bench/NOTES.md, not part of
// the build): explicit families built from a run's frame or a lattice, in the engine's sliced-ELL
// layout, a timer and an upload.
#pragma once

#include <cuda_runtime.h>

#include <algorithm>
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

// Families of every particle within `delta` (a cell grid of side delta), sorted by partner, in the
// sliced-ELL layout of the engine (BondsView::slot); each slot's 16-bit surface factor drawn from
// base .. base + spread - 1.
static Families build(const std::vector<float>& pos, float delta, uint32_t base, uint32_t spread) {
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
      f.surface[f.slot(i, k)] = uint16_t(base + rng() % spread);
    }
  }
  return f;
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

// A bond's stretch at the current positions (the engine's bond_geometry, PMB): s, |xi|, 1/|y|, y.
struct Stretch {
  float s, r0, inv_r, yx, yy, yz;
};

__device__ __forceinline__ Stretch stretch(float4 ri, float4 ui, float4 rj, float4 uj) {
  const float xx = rj.x - ri.x, xy = rj.y - ri.y, xz = rj.z - ri.z;
  const float ex = uj.x - ui.x, ey = uj.y - ui.y, ez = uj.z - ui.z;
  const float yx = xx + ex, yy = xy + ey, yz = xz + ez;
  const float r02 = xx * xx + xy * xy + xz * xz, r2 = yx * yx + yy * yy + yz * yz;
  const float inv_r0 = rsqrtf(r02), r0 = r02 * inv_r0;
  const float inv_r = r2 >= 1.17549435e-38f ? rsqrtf(r2) : 0.f, r = r2 * inv_r;
  const float e = __fdividef(2.f * (xx * ex + xy * ey + xz * ez) + (ex * ex + ey * ey + ez * ez), r + r0);
  return {e * inv_r0, r0, inv_r, yx, yy, yz};
}

// The screened pass's sums over a particle's bonds.
struct Bond {
  float3 f;
  float smin, nearest;
};

__device__ __forceinline__ void accumulate(const Stretch& b, float w, Bond& acc) {
  acc.nearest = fmaxf(acc.nearest, b.s);
  acc.smin = fminf(b.s, acc.smin);
  const float c = b.s * w * b.inv_r;
  acc.f.x += c * b.yx;
  acc.f.y += c * b.yy;
  acc.f.z += c * b.yz;
}

// A partial volume (volume_fraction): 1 up to delta - lambda/2, then falling linearly.
__device__ __forceinline__ float partial_volume(float r0, float horizon, float spacing) {
  const float half = 0.5f * spacing;
  return r0 <= horizon - half ? 1.f : __fdividef(horizon + half - r0, spacing);
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

// The particles' records as the engine keeps them: rest (position, volume lambda^3) and
// displacement (a random micrometre, strain limit 1e-3).
static void particle_records(const std::vector<float>& pos, float spacing, std::vector<float4>& rest,
                             std::vector<float4>& disp) {
  const size_t n = pos.size() / 3;
  rest.resize(n);
  disp.resize(n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1e-6f, 1e-6f);
  for (size_t i = 0; i < n; ++i) {
    rest[i] = make_float4(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], spacing * spacing * spacing);
    disp[i] = make_float4(u(rng), u(rng), u(rng), 1e-3f);
  }
}

// The particle's sums over its team, written by the team's first lane.
template <int T>
__device__ __forceinline__ void finish(int i, Bond acc, float4* force, int lane) {
  acc.f.x = team_sum<T>(acc.f.x);
  acc.f.y = team_sum<T>(acc.f.y);
  acc.f.z = team_sum<T>(acc.f.z);
  acc.smin = team_min<T>(acc.smin);
  acc.nearest = team_max<T>(acc.nearest);
  if (lane == 0) force[i] = make_float4(acc.f.x, acc.f.y, acc.f.z, acc.smin + 0.f * acc.nearest);
}

// The particles: a run's frame (`points.ply DELTA LAMBDA`) or a lattice (`--lattice N`: N^3
// particles at spacing 1 mm, delta 3.015 lambda). False where the arguments (the usage printed) or
// the file are bad.
struct Input {
  std::vector<float> pos;
  float delta = 0, spacing = 0;
  std::string what;
};

static bool read_input(int argc, char** argv, Input& in) {
  if (argc < 3 || (std::string(argv[1]) != "--lattice" && argc < 4)) {
    std::fprintf(stderr, "usage: %s points.ply DELTA LAMBDA | %s --lattice N\n", argv[0], argv[0]);
    return false;
  }
  if (std::string(argv[1]) == "--lattice") {
    const int m = std::atoi(argv[2]);
    in.spacing = 1e-3f;
    in.delta = 3.015f * in.spacing;
    for (int z = 0; z < m; ++z)
      for (int y = 0; y < m; ++y)
        for (int x = 0; x < m; ++x)
          in.pos.insert(in.pos.end(), {x * in.spacing, y * in.spacing, z * in.spacing});
    in.what = "explicit lattice " + std::to_string(m) + "^3";
  } else {
    // A frame's points_NNNNN.ply: binary, x y z first, every property 4 bytes.
    FILE* fp = std::fopen(argv[1], "rb");
    if (!fp) return false;
    char line[256];
    long vertices = 0;
    int properties = 0;
    while (std::fgets(line, sizeof line, fp) && std::strncmp(line, "end_header", 10) != 0) {
      std::sscanf(line, "element vertex %ld", &vertices);
      if (std::strncmp(line, "property", 8) == 0) ++properties;
    }
    std::vector<float> row(static_cast<size_t>(properties));
    for (long v = 0; v < vertices; ++v) {
      if (std::fread(row.data(), 4, row.size(), fp) != row.size()) {
        std::fclose(fp);
        return false;
      }
      in.pos.insert(in.pos.end(), {row[0], row[1], row[2]});
    }
    std::fclose(fp);
    in.delta = std::atof(argv[2]);
    in.spacing = std::atof(argv[3]);
    in.what = argv[1];
  }
  return !in.pos.empty();
}
