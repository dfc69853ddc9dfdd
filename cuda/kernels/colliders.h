// Rigid colliders in `bodyforces` (kernel 5): each analytic shape (views.h Collider) pushes the
// particles that reach into it. A particle is a ball of radius a = V^(1/3) / 2; pressed in by d
// (its centre within a of the surface, or inside) it feels the penalty K V^(1/3) d along the
// surface normal, less the damping of the normal push (c = 2 zeta sqrt(k m)), never pulling;
// and Coulomb friction against its velocity relative to the surface: the force that stops the
// sliding within a step while that stays within mu_s times the push, else mu_d times the push.
// Or LAMMPS's `fix indent` law (kLawLammpsIndent): a particle whose centre is d inside the shape
// feels K d^2 along the normal, K in N/m^2 (LAMMPS `units si`), with no damping or friction.
#pragma once

#include <cmath>

#include "cuda/views.h"

namespace pd {

// Signed distance from the shape's surface (negative inside) and the outward unit normal, at a
// point q in the shape's frame.
struct SurfacePoint {
  real distance;
  Vec3 normal;
};

PD_HD inline real clamp_real(real x, real lo, real hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}

// A direction from q (or `fallback` at q = 0).
PD_HD inline Vec3 unit_or(Vec3 q, Vec3 fallback) {
  const real len = length(q);
  return len > real(0) ? (real(1) / len) * q : fallback;
}

PD_HD inline SurfacePoint box_surface(Vec3 q, Vec3 h) {
  const Vec3 a{std::abs(q.x) - h.x, std::abs(q.y) - h.y, std::abs(q.z) - h.z};
  const Vec3 sign{q.x < 0 ? real(-1) : real(1), q.y < 0 ? real(-1) : real(1), q.z < 0 ? real(-1) : real(1)};
  if (a.x > 0 || a.y > 0 || a.z > 0) {  // outside: from the nearest point of the box
    const Vec3 out{a.x > 0 ? a.x * sign.x : real(0), a.y > 0 ? a.y * sign.y : real(0),
                   a.z > 0 ? a.z * sign.z : real(0)};
    const real d = length(out);
    return {d, (real(1) / d) * out};
  }
  // Inside: through the nearest face.
  if (a.x >= a.y && a.x >= a.z) return {a.x, {sign.x, 0, 0}};
  if (a.y >= a.z) return {a.y, {0, sign.y, 0}};
  return {a.z, {0, 0, sign.z}};
}

PD_HD inline SurfacePoint cylinder_surface(Vec3 q, real radius, real half) {
  const real r = std::sqrt(q.x * q.x + q.z * q.z);
  const Vec3 radial = r > real(0) ? Vec3{q.x / r, 0, q.z / r} : Vec3{1, 0, 0};
  const Vec3 axial{0, q.y < 0 ? real(-1) : real(1), 0};
  const real dr = r - radius, dy = std::abs(q.y) - half;
  if (dr > 0 && dy > 0) {  // beyond the rim
    const real d = std::sqrt(dr * dr + dy * dy);
    return {d, (dr / d) * radial + (dy / d) * axial};
  }
  if (dr > dy) return {dr, radial};
  return {dy, axial};
}

PD_HD inline SurfacePoint shape_surface(const Collider& c, Vec3 q) {
  switch (c.shape) {
    case kColliderSphere:
      return {length(q) - c.size.x, unit_or(q, {0, 1, 0})};
    case kColliderBox:
      return box_surface(q, c.size);
    case kColliderCapsule: {
      const Vec3 d = q - Vec3{0, clamp_real(q.y, -c.size.y, c.size.y), 0};
      return {length(d) - c.size.x, unit_or(d, {1, 0, 0})};
    }
    case kColliderCylinder:
      return cylinder_surface(q, c.size.x, c.size.y);
    default:  // kColliderPlane
      return {q.y, {0, 1, 0}};
  }
}

// The shape's surface at world point x: distance and world normal.
PD_HD inline SurfacePoint collider_surface(const Collider& c, Vec3 x) {
  const real* m = c.rotation;
  const Vec3 d = x - c.center;
  const Vec3 q{m[0] * d.x + m[3] * d.y + m[6] * d.z, m[1] * d.x + m[4] * d.y + m[7] * d.z,
               m[2] * d.x + m[5] * d.y + m[8] * d.z};  // R^T (x - centre)
  const SurfacePoint s = shape_surface(c, q);
  const Vec3 n{m[0] * s.normal.x + m[1] * s.normal.y + m[2] * s.normal.z,
               m[3] * s.normal.x + m[4] * s.normal.y + m[5] * s.normal.z,
               m[6] * s.normal.x + m[7] * s.normal.y + m[8] * s.normal.z};
  return {s.distance, n};
}

// The force of collider c on a particle at x with velocity v, volume `volume` and mass `mass`
// over a step of dt.
PD_HD inline Vec3 collider_force(const Collider& c, Vec3 x, Vec3 v, real volume, real mass, real dt) {
  const SurfacePoint s = collider_surface(c, x);
  if (c.law == kLawLammpsIndent) {
    const real inside = -s.distance;
    return inside > real(0) ? (c.stiffness * inside * inside) * s.normal : Vec3{0, 0, 0};
  }
  const real size = std::cbrt(volume);
  const real depth = real(0.5) * size - s.distance;
  if (!(depth > real(0))) return {0, 0, 0};
  const Vec3 relative = v - (c.velocity + cross(c.omega, x - c.center));
  const real approach = dot(relative, s.normal);  // > 0: separating
  const real k = c.stiffness * size;
  const real push = max_of(k * depth - real(2) * c.damping * std::sqrt(k * mass) * approach, real(0));
  Vec3 f = push * s.normal;
  const Vec3 slide = relative - approach * s.normal;
  const real speed = length(slide);
  if (speed > real(0) && push > real(0)) {
    const real stop = mass * speed / dt;  // the force that ends the sliding within the step
    const real friction = stop <= c.friction_static * push ? stop : c.friction_dynamic * push;
    f -= (friction / speed) * slide;
  }
  return f;
}

// Every collider's force on particle i.
PD_HD inline Vec3 colliders_force(int32_t i, const ParticlesView& p, const StepParams& sp) {
  Vec3 f{0, 0, 0};
  const int64_t count = sp.colliders.size;
  if (count == 0) return f;
  const Vec3 x = p.position(i);
  const real mass = real(1) / p.inv_mass[i];
  for (int64_t k = 0; k < count; ++k)
    f += collider_force(sp.colliders[k], x, p.vel[i], p.volume(i), mass, sp.dt);
  return f;
}

// What the particles do to a free collider: the sum of the reactions to its forces, and their
// moment about its centre (double sums, added in the backend's reduction order).
struct Wrench {
  double fx = 0, fy = 0, fz = 0;  // force [N]
  double tx = 0, ty = 0, tz = 0;  // torque about the centre [N m]
};

PD_HD inline Wrench operator+(const Wrench& a, const Wrench& b) {
  return {a.fx + b.fx, a.fy + b.fy, a.fz + b.fz, a.tx + b.tx, a.ty + b.ty, a.tz + b.tz};
}

// Particle i's reaction on collider c: minus the force c puts on it (as bodyforces computed it).
PD_HD inline Wrench collider_reaction(int32_t i, const ParticlesView& p, const Collider& c, real dt) {
  const Vec3 x = p.position(i);
  const Vec3 f = collider_force(c, x, p.vel[i], p.volume(i), real(1) / p.inv_mass[i], dt);
  if (f.x == 0 && f.y == 0 && f.z == 0) return {};
  const Vec3 r = x - c.center;
  const Vec3 t = cross(r, f);
  return {-double(f.x), -double(f.y), -double(f.z), -double(t.x), -double(t.y), -double(t.z)};
}

}  // namespace pd
