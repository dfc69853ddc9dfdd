// What a run writes: one FrameData per output frame and one RestData (reference configuration)
// per run. Writers store vectors and scalars as float32 whatever `real` is.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "cuda/vec3.h"

namespace pd {

struct FrameData {
  int64_t frame = 0;                     // output frame number
  int64_t step = 0;                      // simulation step
  double time = 0;                       // simulated time [s]
  std::vector<Vec3> position, velocity;  // current positions [m], velocities [m/s]
  std::vector<float> damage;             // broken fraction of each particle's bonds, in [0,1]
  std::vector<int32_t> body;             // body index
  std::vector<int32_t> component;        // connected fragment id (may be empty: then not written)

  size_t size() const { return position.size(); }
};

struct RestData {
  std::vector<Vec3> position;     // reference positions [m]
  std::vector<float> volume;      // [m^3]
  std::vector<int32_t> body;      // body index
  std::vector<int32_t> material;  // index into the material table

  size_t size() const { return position.size(); }
};

// "frame_00042.<extension>": the name of a frame's file inside the output directory.
inline std::string frame_file_name(int64_t frame, std::string_view extension) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%05lld", static_cast<long long>(frame));
  return "frame_" + std::string(digits) + "." + std::string(extension);
}

// Throws std::invalid_argument unless every per-particle array has one entry per particle
// (`component` may also be empty).
inline void check_sizes(const FrameData& f) {
  size_t n = f.size();
  bool ok = f.velocity.size() == n && f.damage.size() == n && f.body.size() == n &&
            (f.component.empty() || f.component.size() == n);
  if (!ok) throw std::invalid_argument("FrameData: per-particle arrays differ in length");
}

inline void check_sizes(const RestData& r) {
  size_t n = r.size();
  bool ok = r.volume.size() == n && r.body.size() == n && r.material.size() == n;
  if (!ok) throw std::invalid_argument("RestData: per-particle arrays differ in length");
}

// Vectors as a flat float32 array x0 y0 z0 x1 ..., the layout both file formats store.
inline std::vector<float> to_float32(const std::vector<Vec3>& v) {
  std::vector<float> out;
  out.reserve(3 * v.size());
  for (const Vec3& p : v) {
    out.push_back(static_cast<float>(p.x));
    out.push_back(static_cast<float>(p.y));
    out.push_back(static_cast<float>(p.z));
  }
  return out;
}

// Inverse of to_float32; `flat.size()` must be a multiple of 3.
inline std::vector<Vec3> from_float32(const std::vector<float>& flat) {
  std::vector<Vec3> out(flat.size() / 3);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = {real(flat[3 * i]), real(flat[3 * i + 1]), real(flat[3 * i + 2])};
  return out;
}

}  // namespace pd
