// Reflection and refraction at a smooth dielectric interface (glass), host and device.
//
// Fresnel: the exact dielectric equations for unpolarised light (the mean of the s and p
// reflectances), not Schlick's approximation. Glass rays leave the dense medium at every exit
// face, and there Schlick's curve written with the incident angle is wrong near the critical
// angle (it does not reach 1 at total internal reflection); the exact form handles entry, exit
// and total internal reflection with one formula and costs one square root more per interface,
// nothing next to the kd-tree traversal. Reflectance and transmittance are computed from their
// own amplitude coefficients, so R + T = 1 is a check of the formulas (tests/render).
#pragma once

#include "render/geometry.h"

namespace pd {

struct Fresnel {
  real reflect;   // R: fraction of the power reflected
  real transmit;  // T: fraction transmitted (0 under total internal reflection)
  real cos_t;     // cosine of the refraction angle (0 under total internal reflection)
};

// Light arriving at angle acos(cos_i) (cos_i in [0, 1]) from a medium of index n1 onto one of
// index n2.
PD_HD inline Fresnel fresnel_dielectric(real cos_i, real n1, real n2) {
  cos_i = clamp01(cos_i);
  const real eta = n1 / n2;
  const real sin2_t = eta * eta * (1 - cos_i * cos_i);
  if (sin2_t >= 1) return {real(1), real(0), real(0)};  // total internal reflection
  const real cos_t = std::sqrt(1 - sin2_t);
  // Amplitude coefficients, s (perpendicular) and p (parallel) polarisation.
  const real rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const real rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  const real ts = 2 * n1 * cos_i / (n1 * cos_i + n2 * cos_t);
  const real tp = 2 * n1 * cos_i / (n2 * cos_i + n1 * cos_t);
  // Power: the transmitted beam's intensity scales with n2 cos_t / (n1 cos_i).
  const real power = cos_i > 0 ? (n2 * cos_t) / (n1 * cos_i) : real(0);
  return {real(0.5) * (rs * rs + rp * rp), real(0.5) * power * (ts * ts + tp * tp), cos_t};
}

// Mirror direction of d about the unit normal n (either side).
PD_HD inline Vec3 reflect(Vec3 d, Vec3 n) {
  return d - (2 * dot(d, n)) * n;
}

// Refraction of the unit direction d through the interface of unit normal n facing against d
// (dot(d, n) < 0), from index n1 into n2; cos_t from fresnel_dielectric (Snell's law in vector
// form: eta d + (eta cos_i - cos_t) n).
PD_HD inline Vec3 refract(Vec3 d, Vec3 n, real n1, real n2, real cos_t) {
  const real eta = n1 / n2;
  const real cos_i = -dot(d, n);
  return normalize(eta * d + (eta * cos_i - cos_t) * n);
}

}  // namespace pd
