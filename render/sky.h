// The built-in procedural sky: a zenith-to-horizon gradient over a darker ground, plus a sun
// disc. It lights the scene (projected to 9 SH coefficients for diffuse light; the sun alone
// for the specular highlight) and is the background that rays missing everything see.
#pragma once

#include "render/sh.h"

namespace pd {

struct Sky {
  Vec3 zenith{real(0.30), real(0.48), real(0.85)};         // linear RGB radiance straight up
  Vec3 horizon{real(0.80), real(0.85), real(0.92)};        // at the horizon
  Vec3 ground{real(0.32), real(0.30), real(0.28)};         // below the horizon
  Vec3 sun_direction{real(0.45), real(0.8), real(0.4)};    // towards the sun (y is up); normalised on use
  Vec3 sun_irradiance{real(1.9), real(1.75), real(1.55)};  // on a surface facing the sun
  real sun_angular_radius = real(0.02);                    // [rad]
};

// Solid angle of the sun disc.
PD_HD inline real sun_solid_angle(const Sky& s) {
  return real(2 * 3.14159265358979323846) * (1 - std::cos(s.sun_angular_radius));
}

// Radiance of the gradient and ground along unit direction w (the sun not included).
PD_HD inline Vec3 sky_gradient(const Sky& s, Vec3 w) {
  if (w.y >= 0) return lerp(s.horizon, s.zenith, std::sqrt(w.y));
  return lerp(s.horizon, s.ground, clamp01(-8 * w.y));  // quick fade into the ground colour
}

// What a ray leaving the scene along unit direction w sees: gradient plus the sun disc.
// `sun` must be the normalised sun direction.
PD_HD inline Vec3 sky_radiance(const Sky& s, Vec3 sun, Vec3 w) {
  const Vec3 g = sky_gradient(s, w);
  if (dot(w, sun) < std::cos(s.sun_angular_radius)) return g;
  return g + (real(1) / sun_solid_angle(s)) * s.sun_irradiance;
}

// SH coefficients of the whole sky: the gradient by quadrature, the sun disc analytically as
// a small source (L_lm += E_sun Y_lm(sun)).
Sh9 sky_sh9(const Sky& s);

}  // namespace pd
