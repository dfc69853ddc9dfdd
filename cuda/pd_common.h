// Macros and scalar types shared by host (g++) and device (nvcc) code.
// Kernel bodies are PD_HD inline functions so one source compiles for both backends.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#if defined(__CUDACC__)
#define PD_HD __host__ __device__
#else
#define PD_HD
#endif

#if defined(__CUDA_ARCH__)
#define PD_TRAP() __trap()
#else
#define PD_TRAP() std::abort()
#endif

// Bounds checks of kernel views (ArrayView, cuda/array_view.h): compiled in with
// PERIFRAC_BOUNDS_CHECKS (the cpu-asan and cuda-debug presets), free otherwise. A failed check
// prints the index, the length and the place (stderr on the CPU, the device printf buffer on the
// GPU) and stops: abort on the CPU, a trap on the GPU (the launch then fails).
#if defined(__CUDA_ARCH__)
#define PD_INDEX_MESSAGE(...) printf(__VA_ARGS__)
#else
#define PD_INDEX_MESSAGE(...) std::fprintf(stderr, __VA_ARGS__)
#endif
#if defined(PERIFRAC_BOUNDS_CHECKS)
#define PD_CHECK_INDEX(i, n)                                                                               \
  do {                                                                                                     \
    if ((i) < 0 || (i) >= (n)) {                                                                           \
      PD_INDEX_MESSAGE("perifrac: index %lld out of [0, %lld) at %s:%d\n", (long long)(i), (long long)(n), \
                       __FILE__, __LINE__);                                                                \
      PD_TRAP();                                                                                           \
    }                                                                                                      \
  } while (0)
#else
#define PD_CHECK_INDEX(i, n) \
  do {                       \
  } while (0)
#endif

// Unrolling of the per-bond loops on the GPU, so loads of several bonds are in flight at once
// (bench/NOTES.md has the measurements behind the default).
#if !defined(PERIFRAC_BOND_UNROLL)
#define PERIFRAC_BOND_UNROLL 1
#endif
#define PD_PRAGMA(x) _Pragma(#x)
#if defined(__CUDA_ARCH__)
#define PD_UNROLL(n) PD_PRAGMA(unroll n)
#else
#define PD_UNROLL(n)
#endif
#define PD_BOND_LOOP PD_UNROLL(PERIFRAC_BOND_UNROLL)

namespace pd {

// Simulation scalar: float by default, double with -DPERIFRAC_DOUBLE=ON (reference runs).
#if defined(PERIFRAC_DOUBLE)
using real = double;
#else
using real = float;
#endif

}  // namespace pd
