// Double-precision 3-vectors for geometry processing on the host (meshes, particle
// generation). The same type as the scene's Vec3d; kernels use the `real` Vec3 instead.
#pragma once

#include <array>
#include <cmath>

namespace pd {

using Vec3d = std::array<double, 3>;

inline Vec3d operator+(const Vec3d& a, const Vec3d& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3d operator-(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3d operator*(double s, const Vec3d& a) {
  return {s * a[0], s * a[1], s * a[2]};
}
inline double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3d& a) {
  return std::sqrt(dot(a, a));
}
inline double distance2(const Vec3d& a, const Vec3d& b) {
  return dot(a - b, a - b);
}

// Axis-aligned bounding box; empty (lo > hi) until a point is added.
struct Box3d {
  Vec3d lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  void add(const Vec3d& p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::fmin(lo[a], p[a]);
      hi[a] = std::fmax(hi[a], p[a]);
    }
  }
  Vec3d center() const { return 0.5 * (lo + hi); }
  Vec3d size() const { return hi - lo; }
};

}  // namespace pd
