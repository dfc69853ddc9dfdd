// A three-component vector of `real` usable on host and device.
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

#include "cuda/pd_common.h"

namespace pd {

struct Vec3 {
  real x, y, z;
};

PD_HD inline Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
PD_HD inline Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
PD_HD inline Vec3 operator-(Vec3 a) {
  return {-a.x, -a.y, -a.z};
}
PD_HD inline Vec3 operator*(real s, Vec3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
PD_HD inline Vec3 operator*(Vec3 a, real s) {
  return {s * a.x, s * a.y, s * a.z};
}
PD_HD inline Vec3& operator+=(Vec3& a, Vec3 b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
PD_HD inline Vec3& operator-=(Vec3& a, Vec3 b) {
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
PD_HD inline real dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
PD_HD inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
PD_HD inline real length_squared(Vec3 a) {
  return dot(a, a);
}
PD_HD inline real length(Vec3 a) {
  return std::sqrt(dot(a, a));
}
PD_HD inline bool is_finite(Vec3 a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// Per-bond arithmetic on the GPU uses the hardware reciprocal square root and the fast
// division (a few ulp; bench/NOTES.md: the IEEE sequences made the bond loops compute-bound),
// flushing subnormal arguments and results to zero: without .ftz each of them rescales
// subnormals around the hardware instruction, 4 to 6 more instructions per call (bench/NOTES.md).
// A subnormal argument to fast_rsqrt counts as 0 (result +inf): callers treat squared lengths
// below kMinNormal as zero. The CPU and double builds compute exactly. Both ends of a bond run
// the same instructions on the same numbers, so symmetric decisions stay symmetric.
PD_HD inline float fast_rsqrt(float x) {
#if defined(__CUDA_ARCH__)
  float r;
  asm("rsqrt.approx.ftz.f32 %0, %1;" : "=f"(r) : "f"(x));
  return r;
#else
  return 1.0f / std::sqrt(x);
#endif
}
PD_HD inline double fast_rsqrt(double x) {
  return 1.0 / std::sqrt(x);
}
PD_HD inline float fast_divide(float a, float b) {
#if defined(__CUDA_ARCH__)
  float r;
  asm("div.approx.ftz.f32 %0, %1, %2;" : "=f"(r) : "f"(a), "f"(b));
  return r;
#else
  return a / b;
#endif
}
PD_HD inline double fast_divide(double a, double b) {
  return a / b;
}

// A product and a multiply-add whose rounding is written out on the GPU. nvcc fuses a product
// into the add that takes it where it likes, and which of two products it fuses into their sum
// follows the code around them: an edit that left a bond loop's arithmetic alone made it fuse
// the other length's product into |y| + |xi| and moved the vase's impact by an ulp, and then
// everything after it (bench/NOTES.md, "The vase's impact on the GPU"). The bond geometry takes
// these, which fix the choice; the CPU computes the plain expressions, as before (its default
// build has no FMA).
template <class T>
PD_HD inline T pinned_product(T a, T b) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>)
    return __fmul_rn(a, b);
  else
    return __dmul_rn(a, b);
#else
  return a * b;
#endif
}
template <class T>
PD_HD inline T pinned_fma(T a, T b, T c) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>)
    return __fmaf_rn(a, b, c);
  else
    return __fma_rn(a, b, c);
#else
  return a * b + c;
#endif
}

// dot(a, b) with its products fused on the GPU as nvcc fused them in the bond loops: a.y b.y
// rounded, a.x b.x and then a.z b.z added in by multiply-adds.
PD_HD inline real pinned_dot(Vec3 a, Vec3 b) {
#if defined(__CUDA_ARCH__)
  return pinned_fma(a.z, b.z, pinned_fma(a.x, b.x, pinned_product(a.y, b.y)));
#else
  return dot(a, b);
#endif
}

// The smallest normal `real`: squared lengths below it count as zero.
constexpr real kMinNormal = std::numeric_limits<real>::min();

// Larger and smaller of two values that are not NaN: one instruction on the GPU (the
// conditional form must return b when a is NaN, which keeps the compiler from using it).
PD_HD inline real max_of(real a, real b) {
#if defined(__CUDA_ARCH__)
  return fmax(a, b);
#else
  return a > b ? a : b;
#endif
}
PD_HD inline real min_of(real a, real b) {
#if defined(__CUDA_ARCH__)
  return fmin(a, b);
#else
  return a < b ? a : b;
#endif
}

// Four values stored together so a gather is one vector load (16 bytes in float, 32 in
// double): a Vec3 plus one scalar that is read at the same time.
struct alignas(4 * sizeof(real)) Vec4 {
  real x, y, z, w;
};

PD_HD inline Vec3 xyz(Vec4 a) {
  return {a.x, a.y, a.z};
}
PD_HD inline Vec4 with_w(Vec3 a, real w) {
  return {a.x, a.y, a.z, w};
}

}  // namespace pd
