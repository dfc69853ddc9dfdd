// The integration kernels fused with their neighbours in the step where nothing between them
// reads what the first writes for another particle: each fused pass runs the kernels' own
// functions one after the other on a particle, so it gives their bits, and reads and writes the
// particle's records once instead of two or three times (bench/NOTES.md, "The step's small
// kernels fused").
//   position update, then bond-based `init` (kernel 6 + 1): init reads the particle's own
//     limits and bond counts of the last force pass and writes the strain limit beside the
//     displacement the update has just written;
//   gravity, then the velocity update (kernel 5 + 7): gravity alone reads the particle's mass
//     and force (projectiles and colliders, which read positions and pushers, keep their kernel);
//   one step's end and the next one's start (5 + 7, then 6 + 1) where the host does nothing
//   between two steps (no scripted motion, free bodies or moving colliders): the velocity update
//   and the next position update read the same step parameters but for the time, which neither
//   reads, and the same force, held between them (not stored: below).
#pragma once

#include "cuda/kernels/bodyforces.h"
#include "cuda/kernels/init.h"
#include "cuda/kernels/integrate.h"

namespace pd {

// held_force: as position_update's.
template <bool kContact, bool kInit>
PD_HD inline void position_update_with_init(int32_t i, ParticlesView p, BondsView b, const MaterialTable& mt,
                                            const StepParams& sp, ContactView c,
                                            const Vec3* held_force = nullptr) {
  position_update<kContact>(i, p, sp, c, held_force);
  if constexpr (kInit) init_particle<false, false, kNoLattice, false>(i, p, b, mt);
}

template <bool kGravity>
PD_HD inline void velocity_update_with_gravity(int32_t i, ParticlesView p, const StepParams& sp) {
  if constexpr (kGravity) body_forces<false>(i, p, sp);
  velocity_update(i, p, sp);
}

// With gravity, the step's force and weight are held for both halves and not stored: the next
// force pass writes every particle's force before anything reads it (frames and checkpoints
// follow a step's own velocity update, which stores it), 12 bytes a particle fewer. Without,
// each half reads the stored force where it uses it, as the kernels apart do.
template <bool kGravity, bool kContact, bool kInit>
PD_HD inline void velocity_then_position_update(int32_t i, ParticlesView p, BondsView b,
                                                const MaterialTable& mt, const StepParams& sp,
                                                ContactView c) {
  if constexpr (kGravity) {
    const Vec3 f = force_with_gravity(i, p, sp);
    velocity_update(i, p, sp, &f);
    position_update_with_init<kContact, kInit>(i, p, b, mt, sp, c, &f);
  } else {
    velocity_update(i, p, sp);
    position_update_with_init<kContact, kInit>(i, p, b, mt, sp, c);
  }
}

}  // namespace pd
