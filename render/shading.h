// Surface shading (Levine et al. 2014, section 5): diffuse light from the environment's
// 9-coefficient SH irradiance (sh.h; the procedural sky or an .hdr map), a normalised Blinn-Phong
// specular highlight from the sky's sun, opaque materials, and a floor plane with a procedural
// wood texture. No shadows.
#pragma once

#include "render/environment.h"
#include "render/sky.h"

namespace pd {

// Everything the shading reads, prepared on the host (make_shading_params) and passed to the
// kernel by value.
struct ShadingParams {
  Sky sky;
  Vec3 sun{0, 1, 0};           // normalised sun direction
  Sh9 sky_sh;                  // SH coefficients of the environment's radiance
  EnvironmentView env;         // an .hdr map in place of the sky; texel empty: the sky
  real specular = real(0.04);  // Blinn-Phong k_s
  real shininess = 60;         // Blinn-Phong exponent m
  uint8_t floor = 1;           // draw the floor plane y = floor_y
  real floor_y = 0;
  real plank_width = real(0.1);    // wood texture scale [m]
  real fade_distance = real(100);  // the floor fades into the horizon over this distance [m]
};

constexpr real kPi = real(3.14159265358979323846);

// Per-primitive materials.
enum SurfaceMaterial : uint8_t { kMaterialOpaque = 0, kMaterialGlass = 1 };

// Radiance leaving an opaque surface towards `view` (unit, from the surface to the eye).
PD_HD inline Vec3 shade_opaque(const ShadingParams& p, Vec3 normal, Vec3 view, Vec3 albedo) {
  // Diffuse: albedo / pi times the SH irradiance.
  Vec3 irradiance = sh9_irradiance(p.sky_sh, normal);
  irradiance = {rmax(irradiance.x, 0), rmax(irradiance.y, 0), rmax(irradiance.z, 0)};
  Vec3 out = (real(1) / kPi) * mul(albedo, irradiance);
  // Specular: normalised Blinn-Phong, (m + 8) / (8 pi) (n.h)^m, lit by the sun.
  const real n_dot_l = dot(normal, p.sun);
  if (n_dot_l > 0 && p.specular > 0) {
    const Vec3 h = normalize(p.sun + view);
    const real n_dot_h = rmax(dot(normal, h), 0);
    const real f = p.specular * (p.shininess + 8) / (8 * kPi) * std::pow(n_dot_h, p.shininess);
    out += (f * n_dot_l) * p.sky.sun_irradiance;
  }
  return out;
}

// What a ray leaving the scene along unit direction w sees: the .hdr map, else the sky.
PD_HD inline Vec3 background_radiance(const ShadingParams& p, Vec3 w) {
  if (p.env.texel) return environment_radiance(p.env, w);
  return sky_radiance(p.sky, p.sun, w);
}

// The colour the floor fades into far away along `dir`: the background at the horizon.
PD_HD inline Vec3 horizon_radiance(const ShadingParams& p, Vec3 dir) {
  if (!p.env.texel) return p.sky.horizon;
  const real l = std::sqrt(dir.x * dir.x + dir.z * dir.z);
  return environment_radiance(p.env, l > 0 ? Vec3{dir.x / l, 0, dir.z / l} : Vec3{1, 0, 0});
}

// A 32-bit integer hash (Wang / Jenkins style mixing) mapped to [0, 1).
PD_HD inline real hash01(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return real(x >> 8) * real(1.0 / 16777216.0);
}

// Smooth 1D value noise in [0, 1).
PD_HD inline real value_noise(real x, uint32_t seed) {
  const real fl = std::floor(x);
  const real f = x - fl;
  const uint32_t i = uint32_t(int32_t(fl)) * 0x9E3779B1u + seed;
  const real s = f * f * (3 - 2 * f);
  return hash01(i) + s * (hash01(i + 0x9E3779B1u) - hash01(i));
}

// Wood floor albedo at floor point (x, z): planks running along x, each board with its own
// ring centre and tone, wavy growth rings, dark seams between boards.
PD_HD inline Vec3 wood_albedo(real x, real z, real plank_width) {
  const real u = x / plank_width, v = z / plank_width;
  const real row = std::floor(v);
  const uint32_t row_id = uint32_t(int32_t(row));
  const real board_length = 6;
  const real along = u + board_length * hash01(row_id * 7919u + 1u);  // stagger the board ends
  const real board = std::floor(along / board_length);
  const uint32_t id = row_id * 92821u + uint32_t(int32_t(board)) * 68917u;
  // Growth rings around an axis along x below the board, perturbed by noise along the grain.
  const real across = v - row - real(0.5) + real(0.8) * (hash01(id) - real(0.5));
  const real depth = real(0.6) + hash01(id + 3u);
  const real wobble = real(0.08) * value_noise(real(0.5) * u, id) + real(0.02) * value_noise(4 * u, id + 11u);
  const real r = std::sqrt(across * across + depth * depth) + wobble;
  const real ring = r * 9 - std::floor(r * 9);
  const real late = std::pow(ring, real(3));  // thin dark latewood at the end of each ring
  const Vec3 light{real(0.58), real(0.38), real(0.22)}, dark{real(0.30), real(0.17), real(0.08)};
  Vec3 c = lerp(light, dark, real(0.6) * late);
  c = (real(0.8) + real(0.4) * hash01(id + 7u)) * c;  // per-board tone
  // Seams: darken the last few percent at board sides and ends.
  const real side = v - row, end = along / board_length - board;
  if (side < real(0.012) || side > real(0.988) || end < real(0.002) || end > real(0.998)) c = real(0.45) * c;
  return c;
}

// The floor seen along a ray of unit direction `dir` hitting it at `p` from distance t.
PD_HD inline Vec3 shade_floor(const ShadingParams& sp, Vec3 p, Vec3 dir, real t) {
  const Vec3 up{0, 1, 0};
  const Vec3 normal = dir.y < 0 ? up : -up;
  const Vec3 lit = shade_opaque(sp, normal, -dir, wood_albedo(p.x, p.z, sp.plank_width));
  const real fade = 1 - std::exp(-t / sp.fade_distance);
  return lerp(lit, horizon_radiance(sp, dir), fade);
}

}  // namespace pd
