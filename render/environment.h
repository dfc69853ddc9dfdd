// HDR environment maps: a Radiance .hdr (RGBE) image in the equirectangular (latitude-longitude)
// layout, loaded with stb_image, projected onto the 9 SH coefficients for diffuse light (sh.h)
// and looked up by the kernel for the rays that leave the scene.
//
// Layout (y is up): row 0 is the zenith, the last row the nadir; the polar angle theta = acos(y)
// grows linearly down the image. The azimuth phi = atan2(z, x) grows linearly along a row with
// u = 0.5 + phi / (2 pi): the centre column looks along +x, the left and right edges along -x,
// u = 0.75 along +z (three.js's equirectangular convention).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "render/sh.h"

namespace pd {

// What the kernel reads: linear RGB texels, rows from the zenith down. texel empty: none.
struct EnvironmentView {
  ArrayView<const Vec3> texel;
  int32_t width = 0, height = 0;
};

constexpr real kTwoPi = real(2 * 3.14159265358979323846);

// Image coordinates (in texels, continuous: texel (i, j) covers [i, i + 1) x [j, j + 1)) of the
// unit direction w.
PD_HD inline void environment_coords(const EnvironmentView& e, Vec3 w, real* x, real* y) {
  const real u = real(0.5) + std::atan2(w.z, w.x) / kTwoPi;
  const real theta = std::acos(w.y < -1 ? real(-1) : (w.y > 1 ? real(1) : w.y));
  *x = u * real(e.width);
  *y = theta / real(3.14159265358979323846) * real(e.height);
}

// Radiance along unit direction w: bilinear between the four nearest texel centres, wrapping
// around in azimuth and clamped at the poles.
PD_HD inline Vec3 environment_radiance(const EnvironmentView& e, Vec3 w) {
  real x, y;
  environment_coords(e, w, &x, &y);
  x -= real(0.5);
  y -= real(0.5);
  const real fx = std::floor(x), fy = std::floor(y);
  const real sx = x - fx, sy = y - fy;
  int32_t x0 = int32_t(fx) % e.width;
  if (x0 < 0) x0 += e.width;
  const int32_t x1 = x0 + 1 == e.width ? 0 : x0 + 1;
  const int32_t y0 = fy < 0 ? 0 : (int32_t(fy) >= e.height ? e.height - 1 : int32_t(fy));
  const int32_t y1 = y0 + 1 < e.height && fy >= 0 ? y0 + 1 : y0;
  const ArrayView<const Vec3> r0 = e.texel.sub(int64_t(y0) * e.width, e.width);
  const ArrayView<const Vec3> r1 = e.texel.sub(int64_t(y1) * e.width, e.width);
  return lerp(lerp(r0[x0], r0[x1], sx), lerp(r1[x0], r1[x1], sx), sy);
}

// Host-side owner of a loaded map.
struct EnvironmentMap {
  std::string path;  // where it was read from (messages, reports)
  int32_t width = 0, height = 0;
  std::vector<Vec3> texel;  // width * height, rows from the zenith down
  Sh9 sh;                   // environment_sh9 of the texels (set by load_environment)

  EnvironmentView view() const { return {view_of(texel), width, height}; }
};

// A map that cannot be used: a user mistake (what() names the file and what is allowed).
class EnvironmentError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Reads a Radiance .hdr file and projects it onto SH. Throws EnvironmentError "cannot read environment
// '<path>': <reason> (allowed: a Radiance .hdr (RGBE) image in latitude-longitude layout, 2:1)" when the file
// is missing, unreadable, not an .hdr, or not twice as wide as high.
EnvironmentMap load_environment(const std::string& path);

// L_lm of the map, each texel's radiance constant over its patch of the sphere: the sum of texel
// radiance times the integral of Y_lm over the patch, in closed form. Exact (to round-off) for the
// piecewise-constant radiance the texels describe.
Sh9 environment_sh9(const EnvironmentMap& map);

}  // namespace pd
