// Teams of threads per particle: a small scene's bond loops split over several threads. With one
// thread per particle a scene of a few thousand particles runs a few blocks, each thread walking
// its ~120 bonds in turn (bench/NOTES.md: 3,840 particles take 0.05 ms per force kernel on an
// H100, whatever the launch's shape). A team of kThreads lanes of one warp (a power of two, at
// most 32) walks one particle's bonds together, lane l taking bonds l, l + kThreads, ..., and adds
// its partial sums to its team-mates' in a fixed tree of shuffles: every lane ends with the same
// bits, so the decisions after the loop (the screened pass's test) agree, and a run is
// deterministic. Team<1> is the one thread per particle of every other launch: no lanes, no
// shuffles, the same code and bits as before teams existed. Teams run on the GPU only
// (CudaExec::parallel_for_team); the CPU backend runs Team<1>.
#pragma once

#include "cuda/pd_common.h"
#include "cuda/vec3.h"

namespace pd {

template <int kThreads>
struct Team {
  static_assert(kThreads > 1 && kThreads <= 32 && (kThreads & (kThreads - 1)) == 0,
                "a team is 2, 4, 8, 16 or 32 lanes of one warp");
  static constexpr int kSize = kThreads;
  int32_t lane_index;  // 0 .. kThreads - 1
  uint32_t mask;       // the team's lanes within its warp

  PD_HD int32_t lane() const { return lane_index; }
  PD_HD bool leader() const { return lane_index == 0; }
  // Entries q of a 32-bit word this lane visits: q = lane + k kThreads.
  PD_HD uint32_t own_bits() const { return kEveryTeamBit << lane_index; }

  PD_HD float sum(float v) const {
    return butterfly(v, [](float a, float b) { return a + b; });
  }
  PD_HD double sum(double v) const {
    return butterfly(v, [](double a, double b) { return a + b; });
  }
  PD_HD int32_t sum(int32_t v) const {
    return butterfly(v, [](int32_t a, int32_t b) { return a + b; });
  }
  PD_HD Vec3 sum(Vec3 v) const { return {sum(v.x), sum(v.y), sum(v.z)}; }
  PD_HD real min(real v) const {
    return butterfly(v, [](real a, real b) { return min_of(a, b); });
  }
  PD_HD real max(real v) const {
    return butterfly(v, [](real a, real b) { return max_of(a, b); });
  }
  // Lane `src`'s v, in every lane of the team.
  PD_HD real from(int32_t src, real v) const {
#if defined(__CUDA_ARCH__)
    return __shfl_sync(mask, v, src, kThreads);
#else
    (void)src;
    return v;
#endif
  }

 private:
  // Bit 0 of every group of kThreads bits.
  static constexpr uint32_t every_team_bit() {
    uint32_t bits = 0;
    for (int q = 0; q < 32; q += kThreads) bits |= 1u << q;
    return bits;
  }
  static constexpr uint32_t kEveryTeamBit = every_team_bit();

  // log2(kThreads) rounds of exchange with the lane `offset` away: each lane ends with op over all
  // lanes' values, combined in the same tree. op commutes (float addition; min_of and max_of, which
  // on the GPU ignore a NaN), so the two lanes of an exchange agree, and every lane ends equal.
  template <class T, class Op>
  PD_HD T butterfly(T v, Op op) const {
#if defined(__CUDA_ARCH__)
    for (int offset = kThreads / 2; offset > 0; offset /= 2)
      v = op(v, __shfl_xor_sync(mask, v, offset, kThreads));
#endif
    return v;  // (host code never runs a team: CpuExec launches Team<1>)
  }
};

// One thread per particle.
template <>
struct Team<1> {
  static constexpr int kSize = 1;
  PD_HD static constexpr int32_t lane() { return 0; }
  PD_HD static constexpr bool leader() { return true; }
  PD_HD static constexpr uint32_t own_bits() { return ~0u; }
  template <class T>
  PD_HD static T sum(T v) {
    return v;
  }
  PD_HD static real min(real v) { return v; }
  PD_HD static real max(real v) { return v; }
};

// Clears bit q of a lattice particle's intact word after a bond broke, the word's other bits as the
// lane read them (`intact`, bit q already cleared): one thread stores the word, a team's lanes
// (each clearing only the bits it visits) clear their bit atomically.
template <int kThreads>
PD_HD inline void store_intact_word(uint32_t* word, uint32_t intact, [[maybe_unused]] int32_t q) {
  if constexpr (kThreads == 1) {
    *word = intact;
  } else {
#if defined(__CUDA_ARCH__)
    atomicAnd(word, ~(1u << q));
#endif
  }
}

// The team sizes a launch may take (with_bond_threads, cuda/launch.h). No team of 2: the rule
// below never takes it (one thread was as fast or faster in every scene swept but the torus,
// where it was 0.5% behind 4 lanes), and each size is one more instantiation of every bond kernel
// to compile.
constexpr bool valid_bond_threads(int threads) {
  return threads == 1 || threads == 4 || threads == 8 || threads == 16 || threads == 32;
}

// The lanes per particle a run uses, from a sweep of sizes 1 to 32 on an H100 (bench/NOTES.md,
// "Team sizes by scene"). Regular (box-grid) families gain while one thread per particle leaves
// the GPU idle: the best size keeps particles x lanes near kTeamThreads (3,840 particles: 32,
// 20k: 8, 51k and 64k: 4), and from 2 lanes down one thread wins (131k: 1 beats 2 by 10%).
// Explicit (mesh-filled) families spread from tens to hundreds of bonds, so a warp of single
// threads waits on its longest family; lanes share it out at any size measured: 8 up to
// kTeamListedEight (the 149k vase 1.78x), 4 above (the 577k vase 1.10x, the 494k torus of
// Voronoi cells 1.05x). `mesh_filled`: most of the run's particles are not in box grids. A box grid with
// explicit families (--explicit-families) is not: its families are even, and at 1M particles one
// thread beats 4 lanes there by 10-14%.
// `requested` > 0 forces a count. A function of the whole run only (bond_threads.h).
constexpr int64_t kTeamThreads = int64_t(1) << 18;
constexpr int64_t kTeamListedEight = int64_t(1) << 18;
constexpr int bond_threads_for(int64_t particles, bool mesh_filled, int requested) {
  if (requested > 0) return requested;
  int threads = 1;
  while (threads < 32 && particles * 2 * threads <= kTeamThreads) threads *= 2;
  if (threads < 4) threads = 1;
  if (mesh_filled) {
    const int mesh = particles < kTeamListedEight ? 8 : 4;
    if (threads < mesh) threads = mesh;
  }
  return threads;
}

// Threads per block of a run's team launches (CudaExec::set_team_block): 128 where bond-based
// teams walk mesh-filled families of under kShortLaneBonds bonds a lane on average, else 256,
// every other launch's. Short loops finish unevenly, and smaller blocks let an SM start new work
// where half the warps of a block of 256 would still hold it; long ones lose from the partners
// of a warp's neighbours spread over more blocks. Swept on an H200 (bench/NOTES.md, "Team
// launches in blocks of 128"), springforces: the vase (75 bonds a particle, 4 lanes: 19 a lane)
// +1.8%, the gallery's vase (75, 8 lanes: 9) +1.7%, the torus of Voronoi cells at --scale 5
// (531, 8 lanes: 66) +1.5%, at Levine's size (531, 4 lanes: 133) -2.6%. State-based runs keep 256:
// their force and dilatation passes went -1.2 to +4.2% by scene. `requested` > 0
// (PERIFRAC_TEAM_BLOCK) forces a size.
constexpr double kShortLaneBonds = 100;
constexpr int team_block_for(bool mesh_filled, bool state_based, double bonds_per_lane, int requested) {
  if (requested > 0) return requested;
  return mesh_filled && !state_based && bonds_per_lane < kShortLaneBonds ? 128 : 256;
}

// The lanes per particle of the ghost kernels (surface_ghosts.h), from the ghosted particles'
// count: each particle's fit walks its family and its ghosts with 27 sums in registers. (The
// gather from pushed shares on springforces' lanes instead: one thread a particle on the 380k
// twisted bar 0.32 ms against 0.19 ms with 8 lanes; bench/NOTES.md, 2026-11-30.) Swept on an H200
// (bench/NOTES.md, "Teams for the ghost kernels"; both kernels per step, ms): the twisted bar's
// 119k ghosted particles 1 lane 1.17, 4 1.22, 8 1.11, 16 1.75, 32 2.36; the vase's 134k 1.04,
// 1.15, 0.85, 1.43, 1.87; the small twisted bar's 3.8k 0.33 on one lane, 0.065 on 32. So 8 lanes,
// and more while ghosted x lanes leaves the GPU idle. `requested` > 0 (PERIFRAC_BOND_THREADS)
// forces a count.
constexpr int64_t kGhostTeamThreads = int64_t(1) << 19;
constexpr int ghost_threads_for(int64_t ghosted, int requested) {
  if (requested > 0) return requested;
  int threads = 8;
  while (threads < 32 && ghosted * threads < kGhostTeamThreads) threads *= 2;
  return threads;
}

}  // namespace pd
