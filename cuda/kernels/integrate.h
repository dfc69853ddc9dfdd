// Kernels 6 and 7: the two halves of velocity Verlet. Held anchored particles follow their
// group's prescribed motion (AnchorMotion; at rest for a fixed anchor) whatever the forces.
//   position update: v += dt/2 f/m; u += dt v
//   velocity update: v += dt/2 f/m   (with the forces of the new positions)
#pragma once

#include "cuda/kernels/collisions.h"
#include "cuda/views.h"

namespace pd {

// R - I (row major) applied to d.
PD_HD inline Vec3 rotate_minus_identity(const real* m, Vec3 d) {
  return {m[0] * d.x + m[1] * d.y + m[2] * d.z, m[3] * d.x + m[4] * d.y + m[5] * d.z,
          m[6] * d.x + m[7] * d.y + m[8] * d.z};
}

// kContact: also reports the particle when it has left its contact skin (collisions.h).
// held_force: the particle's force where the caller holds it (a fused pass), else p.force[i] is
// read where it is used (null; the compiler then makes the code of the form without it).
template <bool kContact = false>
PD_HD inline void position_update(int32_t i, ParticlesView p, const StepParams& sp, ContactView c = {},
                                  const Vec3* held_force = nullptr) {
  const real dt = sp.dt;
  Vec4 u = p.disp[i];
  Vec3 v = p.vel[i];
  const bool hold = held(i, p, sp);
  if (hold && sp.anchor[p.anchor[i]].scripted) {
    const AnchorMotion& a = sp.anchor[p.anchor[i]];
    const Vec3 d = xyz(p.rest[i]) - a.pivot;
    const Vec3 turned = rotate_minus_identity(a.rotation_minus_identity, d);
    const Vec3 offset = a.offset + turned;
    u = {offset.x, offset.y, offset.z, u.w};
    p.vel[i] = a.velocity + cross(a.omega, d + turned);
  } else {
    if (!hold) {
      v += (real(0.5) * dt * p.inv_mass[i]) * (held_force ? *held_force : p.force[i]);
      p.vel[i] = v;
    }
    u.x += dt * v.x;
    u.y += dt * v.y;
    u.z += dt * v.z;
  }
  p.disp[i] = u;
  if constexpr (kContact)
    if (left_contact_skin(u, c.origin[i], c.shift)) report_mover(i, c);
}

// Whether particle i is below the floor. Its reference position is read only where its
// displacement could take it there: rounding is monotonic, so lowest_rest_y + u_y at or above the
// floor puts X_y + u_y there too (the same answer, 16 bytes a particle fewer while a body falls
// clear of the floor).
PD_HD inline bool below_floor(int32_t i, const ParticlesView& p, const StepParams& sp) {
  const real uy = p.disp[i].y;
  if (sp.lowest_rest_y + uy >= sp.floor_height) return false;
  return p.rest[i].y + uy < sp.floor_height;
}

// An anchor holds its particle against the force on it: it does work -f.v dt on the body.
// The floor y = floor_height reflects the downward velocity of a particle below it with the
// restitution factor (Levine sec. 3); on the full-step velocity, so the ledger records
// exactly the kinetic energy it takes away.
// held_force: as position_update's.
PD_HD inline void velocity_update(int32_t i, ParticlesView p, const StepParams& sp,
                                  const Vec3* held_force = nullptr) {
  if (held(i, p, sp)) {
    const Vec3 v = p.vel[i];
    if (v.x != 0 || v.y != 0 || v.z != 0)
      p.ledger[i].work -= double(sp.dt) * double(dot(held_force ? *held_force : p.force[i], v));
    return;
  }
  Vec3 v = p.vel[i] + (real(0.5) * sp.dt * p.inv_mass[i]) * (held_force ? *held_force : p.force[i]);
  if (sp.floor_enabled && v.y < real(0) && below_floor(i, p, sp)) {
    const double vy = v.y, e = sp.restitution;
    p.ledger[i].work -= 0.5 / double(p.inv_mass[i]) * vy * vy * (1.0 - e * e);
    v.y = -sp.restitution * v.y;
  }
  p.vel[i] = v;
}

}  // namespace pd
