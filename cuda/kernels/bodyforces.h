// Kernel 5, `bodyforces`: gravity, spherical projectiles (Levine eq. 7) and rigid colliders
// (colliders.h). The floor
// (Levine sec. 3) acts on the full-step velocity in the velocity update (integrate.h).
#pragma once

#include <cmath>

#include "cuda/kernels/colliders.h"
#include "cuda/views.h"

namespace pd {

// Magnitude of Levine eq. 7 at distance d from the projectile centre: zero outside
// [3r/4, 3r/2], K_S r^2 at d = r.
PD_HD inline real projectile_magnitude(real d, real radius, real strength) {
  const real lo = real(0.75) * radius, hi = real(1.5) * radius;
  if (d < lo || d > hi) return real(0);
  const real g = real(16) * (d - lo) * (d - hi) * (d - hi);
  return strength * std::pow(g, real(2) / real(3));
}

// Direction halfway between the projectile's unit velocity and the unit repulsion from
// its centre; pure repulsion for a projectile at rest.
PD_HD inline Vec3 projectile_force(Vec3 x, const Projectile& pr, real time) {
  const Vec3 c = pr.center0 + time * pr.velocity;
  const Vec3 d = x - c;
  const real dist = length(d);
  const real mag = projectile_magnitude(dist, pr.radius, pr.strength);
  if (mag == real(0) || dist <= real(0)) return {0, 0, 0};
  Vec3 dir = (real(1) / dist) * d;
  const real speed = length(pr.velocity);
  if (speed > real(0)) dir += (real(1) / speed) * pr.velocity;
  const real len = length(dir);
  if (len <= real(0)) return {0, 0, 0};
  return (mag / len) * dir;
}

// The force on particle i with its weight added, as body_forces<false> stores it.
PD_HD inline Vec3 force_with_gravity(int32_t i, const ParticlesView& p, const StepParams& sp) {
  const real mass = real(1) / p.inv_mass[i];
  const Vec3 fp{0, 0, 0};
  return p.force[i] + mass * sp.gravity + fp;
}

// The ledger records the work of the projectiles and colliders over the step (force times the
// half-step velocity times dt), for the particles they push (the others' ledgers are not touched).
// kPushers false (no projectiles, no colliders): gravity alone, which reads neither the position
// nor the pushers' code, so the kernel moves 28 bytes a particle at full occupancy; the same bits.
template <bool kPushers = true>
PD_HD inline void body_forces(int32_t i, ParticlesView p, const StepParams& sp) {
  if constexpr (!kPushers) {
    p.force[i] = force_with_gravity(i, p, sp);
  } else {
    // (The position read before the mass, as the pushers' loops want it: read after it, the kernel
    // with projectiles ran 12% slower on the 1M glass plate.)
    const Vec3 x = p.position(i);
    const real mass = real(1) / p.inv_mass[i];
    Vec3 fp{0, 0, 0};
    for (int32_t k = 0; k < sp.n_projectiles; ++k) fp += projectile_force(x, sp.projectile[k], sp.time);
    if (sp.colliders.size > 0) fp += colliders_force(i, p, sp);
    p.force[i] = p.force[i] + mass * sp.gravity + fp;
    if (fp.x != 0 || fp.y != 0 || fp.z != 0) p.ledger[i].work += double(sp.dt) * double(dot(fp, p.vel[i]));
  }
}

}  // namespace pd
