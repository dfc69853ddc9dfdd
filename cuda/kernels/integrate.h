// Kernels 6 and 7: the two halves of velocity Verlet. Anchored particles keep their
// prescribed velocity (zero for a fixed anchor) whatever the forces.
//   position update: v += dt/2 f/m; u += dt v
//   velocity update: v += dt/2 f/m   (with the forces of the new positions)
#pragma once

#include "../views.h"

namespace pd {

PD_HD inline void position_update(int32_t i, ParticlesView p, real dt) {
  Vec4 u = p.disp[i];
  Vec3 v = p.vel[i];
  if (!(p.flags[i] & kAnchored)) {
    v += (real(0.5) * dt * p.inv_mass[i]) * p.force[i];
    p.vel[i] = v;
  }
  u.x += dt * v.x;
  u.y += dt * v.y;
  u.z += dt * v.z;
  p.disp[i] = u;
}

// An anchor holds its particle against the force on it: it does work -f.v dt on the body.
PD_HD inline void velocity_update(int32_t i, ParticlesView p, real dt) {
  if (p.flags[i] & kAnchored) {
    const Vec3 v = p.vel[i];
    if (v.x != 0 || v.y != 0 || v.z != 0) p.ledger[i].work -= double(dt) * double(dot(p.force[i], v));
    return;
  }
  p.vel[i] += (real(0.5) * dt * p.inv_mass[i]) * p.force[i];
}

}  // namespace pd
