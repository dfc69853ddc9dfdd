// Pinhole camera, primary rays and the fixed per-pixel sample pattern.
#pragma once

#include <cmath>
#include <stdexcept>

#include "render/geometry.h"

namespace pd {

struct Camera {
  Vec3 eye{0, 0, 1};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  real vfov_degrees = 40;  // vertical field of view
};

// The camera as the kernel uses it: an orthonormal frame and the image-plane half extents.
struct CameraFrame {
  Vec3 eye, forward, right, up;
  real half_height, half_width;  // at unit distance along `forward`
  int32_t width, height;         // image size [pixels]
};

// Throws std::invalid_argument for a degenerate camera (eye at look_at, field of view outside
// (0, 180) degrees) or an empty image. A view along `up` (straight down or up) takes -z, then x,
// as the image's up instead.
inline CameraFrame camera_frame(const Camera& c, int width, int height) {
  const Vec3 view = c.look_at - c.eye;
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: the image is empty");
  if (!(c.vfov_degrees > 0 && c.vfov_degrees < 180))
    throw std::invalid_argument("camera: fov not in (0, 180)");
  if (!(length(view) > 0)) throw std::invalid_argument("camera: eye and look-at coincide");
  CameraFrame f;
  f.eye = c.eye;
  f.forward = normalize(view);
  Vec3 right = cross(f.forward, c.up);
  for (const Vec3 up : {Vec3{0, 0, -1}, Vec3{1, 0, 0}})
    if (!(length(right) > real(1e-6) * length(c.up))) right = cross(f.forward, up);
  if (!(length(right) > 0)) throw std::invalid_argument("camera: the view direction is not finite");
  f.right = normalize(right);
  f.up = cross(f.right, f.forward);
  f.half_height = real(std::tan(0.5 * double(c.vfov_degrees) * 3.14159265358979323846 / 180));
  f.half_width = f.half_height * real(width) / real(height);
  f.width = width;
  f.height = height;
  return f;
}

// The ray through image point (px, py) in pixel units, (0, 0) the top-left image corner.
PD_HD inline Ray camera_ray(const CameraFrame& f, real px, real py) {
  const real sx = (2 * px / real(f.width) - 1) * f.half_width;
  const real sy = (1 - 2 * py / real(f.height)) * f.half_height;
  const Vec3 d = normalize(f.forward + sx * f.right + sy * f.up);
  return make_ray(f.eye, d, 0, INFINITY);
}

// Base-2 radical inverse of k (van der Corput), in [0, 1).
PD_HD inline real radical_inverse2(uint32_t k) {
  k = (k << 16) | (k >> 16);
  k = ((k & 0x00ff00ffu) << 8) | ((k & 0xff00ff00u) >> 8);
  k = ((k & 0x0f0f0f0fu) << 4) | ((k & 0xf0f0f0f0u) >> 4);
  k = ((k & 0x33333333u) << 2) | ((k & 0xccccccccu) >> 2);
  k = ((k & 0x55555555u) << 1) | ((k & 0xaaaaaaaau) >> 1);
  return real(double(k) * (1.0 / 4294967296.0));
}

// Offset (u, v) in [0, 1)^2 of sample k of `spp` inside a pixel: a Hammersley set shifted by
// half a stratum, identical for every pixel and frame. Each of the spp columns and (for powers
// of two) each elementary rectangle holds one sample; spp = 1 is the pixel centre.
PD_HD inline void pixel_sample(int k, int spp, real* u, real* v) {
  const real inv = real(1) / real(spp);
  *u = (real(k) + real(0.5)) * inv;
  const real r = radical_inverse2(uint32_t(k)) + real(0.5) * inv;
  *v = r < 1 ? r : r - 1;
}

// A 3/4 view from above on `box`: the eye up and to the side of the box centre, far enough
// for the box's bounding sphere to fit the narrower field of view of a width x height image.
inline Camera frame_box(const Box& box, int width, int height, real vfov_degrees = 35) {
  Camera c;
  c.vfov_degrees = vfov_degrees;
  c.look_at = real(0.5) * (box.lo + box.hi);
  const real radius = rmax(real(0.5) * length(box.hi - box.lo), real(1e-6));
  const double half_v = 0.5 * double(vfov_degrees) * 3.14159265358979323846 / 180;
  const double half_h = std::atan(std::tan(half_v) * width / height);
  const double distance = 1.05 * radius / std::sin(half_v < half_h ? half_v : half_h);
  const Vec3 direction =
      normalize(Vec3{real(0.75), real(0.6), real(1.0)});  // azimuth ~37 deg, elevation ~26 deg
  c.eye = c.look_at + real(distance) * direction;
  return c;
}

}  // namespace pd
