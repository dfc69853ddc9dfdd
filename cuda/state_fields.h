// The engine's state, declared once: every per-particle and per-bond array the kernels read or
// write, with its element type, its length, when it exists and what it takes part in. The rest
// is generated from these two lists:
// - the array members of ParticlesView and BondsView (cuda/views.h), bounds-checked views;
// - the engine's buffers, their views, upload sizes and memory accounting
//   (cuda/engine/engine_state.h), and the bytes per particle of the memory budget;
// - EngineSnapshot, save / restore, and the checkpoint file's records (cuda/engine/snapshot.h);
// - ParticleState, what every frame reads back for the output files (Engine::read_state);
// - for a partitioned run, what a ghost copy of a particle receives (the halo column); a
//   particle that moves to another rank takes every field of length kParticles and its slots.
//
// Each entry is X(name, Type, length, when, saved, halo, frame):
//   Type    the element type as the kernels see it; const where the kernels only read it
//   length  kParticles: one per particle; kSlots: one per bond slot of the sliced-ELL families
//           (BondsView::slot); kSlices: one per slice of kSliceWidth particles, plus one
//   when    kForAll; kForStateBased, kForPlastic: state-based / plastic materials only; kForWeakBonds:
//           scenes whose cuts weaken bonds; kForSurface: materials with the surface correction
//           (either model); kForPartitioned: runs over several ranks
//           (cuda/parallel/). Otherwise the array is empty (a null view).
//   saved   kSaved: a run changes it, so checkpoints save it and a restore puts it back bit for
//           bit; kDerived: it follows from the scene (or, for plastic_mirror, from `plastic`)
//   halo    kHaloNone: only the owner reads it; kHaloSetup: a partner's bond or contact reads it
//           and it never changes (sent once); kHaloStep: a partner reads it and it changes every
//           step (sent before the kernel that reads it)
//   frame   kFrameAll / kFrameXyz: read back every frame for the output files (ParticleState),
//           whole or its xyz part (a displacement without tau'); kFrameNone: not
// Adding a field is one line here plus its use in a kernel (and its start value in
// EngineState::upload when that is not zero); checkpoints, views and memory follow.
#pragma once

#include <type_traits>

#include "cuda/vec3.h"

namespace pd {

// Energy that entered or left a particle's books outside its potential and kinetic energy:
// work done on it by projectiles, moving anchors and the floor's restitution, and the elastic
// energy of its bonds at the moment they broke (its end's share). Accumulated in double.
struct Ledger {
  double work = 0;
  double released = 0;
};

enum FieldLength { kParticles, kSlots, kSlices };
enum FieldWhen { kForAll, kForStateBased, kForPlastic, kForWeakBonds, kForSurface, kForPartitioned };
enum FieldSaved { kDerived, kSaved };
enum FieldHalo { kHaloNone, kHaloSetup, kHaloStep };
enum FieldFrame { kFrameNone, kFrameAll, kFrameXyz };

// Per particle (ParticlesView). What a bond reads of its partner is packed into 16-byte records,
// one vector load each.
#define PD_PARTICLE_FIELDS(X)                                                                        \
  /* xyz: reference position X [m]; w: volume V [m^3] */                                             \
  X(rest, const Vec4, kParticles, kForAll, kDerived, kHaloSetup, kFrameNone)                         \
  /* xyz: displacement u [m]; w: effective strain limit tau' (Levine eq. 5), set by `init` */        \
  X(disp, Vec4, kParticles, kForAll, kSaved, kHaloStep, kFrameXyz)                                   \
  /* velocity v [m/s] */                                                                             \
  X(vel, Vec3, kParticles, kForAll, kSaved, kHaloNone, kFrameAll)                                    \
  /* total force on the particle [N] */                                                              \
  X(force, Vec3, kParticles, kForAll, kSaved, kHaloNone, kFrameAll)                                  \
  /* 1/m [1/kg] */                                                                                   \
  X(inv_mass, const real, kParticles, kForAll, kDerived, kHaloNone, kFrameNone)                      \
  /* index into MaterialTable */                                                                     \
  X(material, const uint16_t, kParticles, kForAll, kDerived, kHaloSetup, kFrameNone)                 \
  /* body: bodies do not bond to each other */                                                       \
  X(body, const int32_t, kParticles, kForAll, kDerived, kHaloSetup, kFrameNone)                      \
  /* ParticleFlag bits */                                                                            \
  X(flags, const uint8_t, kParticles, kForAll, kDerived, kHaloNone, kFrameNone)                      \
  /* anchor group of an anchored particle (StepParams::anchor) */                                    \
  X(anchor, const uint8_t, kParticles, kForAll, kDerived, kHaloNone, kFrameNone)                     \
  /* scattered base strain limit tau_i */                                                            \
  X(strain_limit0, const real, kParticles, kForAll, kDerived, kHaloNone, kFrameNone)                 \
  /* minimum bond strain of the last force pass */                                                   \
  X(strain_min, real, kParticles, kForAll, kSaved, kHaloNone, kFrameNone)                            \
  /* unbroken bonds, written by `springforces` */                                                    \
  X(intact, int32_t, kParticles, kForAll, kSaved, kHaloNone, kFrameAll)                              \
  /* energy accounting (Ledger) */                                                                   \
  X(ledger, Ledger, kParticles, kForAll, kSaved, kHaloNone, kFrameNone)                              \
  /* x theta_i (dilatation, set by `init`); y 1/m_i, m_i = sum_j omega |xi|^2 beta V_j over the  */  \
  /* initial family; z phi_i = 1 - intact/initial bonds of the last step (damage, set by `init`); */ \
  /* w (plastic materials) the trial deviatoric norm |t^d| that `plasticity` tests (`init`),  */     \
  /* then its return-mapping factor s, +inf if it never flowed (reads_plastic_history) */            \
  X(state, Vec4, kParticles, kForStateBased, kSaved, kHaloStep, kFrameNone)                          \
  /* the surface correction's factors along x, y, z (set-up, surface_correction.h)              */   \
  X(surface_factor, Vec3, kParticles, kForSurface, kDerived, kHaloSetup, kFrameNone)                 \
  /* index of the particle in the whole run, which orders families and contact lists (order_of) */   \
  X(global_id, const int32_t, kParticles, kForPartitioned, kDerived, kHaloNone, kFrameNone)

// Per bond slot (BondsView), in sliced-ELL layout.
#define PD_BOND_FIELDS(X)                                                                          \
  /* start of each slice's slots; n_slices + 1 entries */                                          \
  X(slice_offset, const int64_t, kSlices, kForAll, kDerived, kHaloNone, kFrameNone)                \
  /* bonds per particle at the start */                                                            \
  X(count, const int32_t, kParticles, kForAll, kDerived, kHaloNone, kFrameNone)                    \
  /* partner index, or ~partner once broken */                                                     \
  X(neighbor, int32_t, kSlots, kForAll, kSaved, kHaloNone, kFrameNone)                             \
  /* e^p of this end's state on the bond [m] */                                                    \
  X(plastic, real, kSlots, kForPlastic, kSaved, kHaloNone, kFrameNone)                             \
  /* e^p of the partner's end of the same bond, kept at this end's slot by `springforces`      */  \
  /* (plasticity.h), so that it reads and updates both ends' history at its own slots; rebuilt */  \
  /* from `plastic` after a restore                                                             */ \
  X(plastic_mirror, real, kSlots, kForPlastic, kDerived, kHaloNone, kFrameNone)                    \
  /* per slot, the factor q/255 on the bond's strain limit (cuda/engine/bond_cuts.h), the same  */ \
  /* in both stored directions                                                                  */ \
  X(strength, const uint8_t, kSlots, kForWeakBonds, kDerived, kHaloNone, kFrameNone)               \
  /* per slot, the surface correction's factor on the bond in steps of 2^-12 (on its           */  \
  /* micromodulus, bond-based; on its influence function, state-based; set-up,                 */  \
  /* surface_correction.h), the same both ways                                                 */  \
  X(surface_bond, uint16_t, kSlots, kForSurface, kDerived, kHaloNone, kFrameNone)

// All of them, particles first.
#define PD_STATE_FIELDS(X) PD_PARTICLE_FIELDS(X) PD_BOND_FIELDS(X)

// PD_IF_SAVED(saved, code): `code` for a kSaved field only (token pasting on the table's column).
#define PD_IF_SAVED_kSaved(...) __VA_ARGS__
#define PD_IF_SAVED_kDerived(...)
#define PD_IF_SAVED(saved, ...) PD_IF_SAVED_##saved(__VA_ARGS__)

// PD_FRAME_MEMBER_TYPE(frame, Type): the element type a frame reads back (none: no member).
#define PD_IF_FRAME_kFrameAll(...) __VA_ARGS__
#define PD_IF_FRAME_kFrameXyz(...) __VA_ARGS__
#define PD_IF_FRAME_kFrameNone(...)
#define PD_IF_FRAME(frame, ...) PD_IF_FRAME_##frame(__VA_ARGS__)
#define PD_FRAME_TYPE_kFrameAll(Type) std::remove_const_t<Type>
#define PD_FRAME_TYPE_kFrameXyz(Type) Vec3
#define PD_FRAME_TYPE_kFrameNone(Type) void
#define PD_FRAME_TYPE(frame, Type) PD_FRAME_TYPE_##frame(Type)

// Bytes a particle's own arrays take (every field of length kParticles that exists for a run
// with these features).
struct FieldNeeds {
  bool state_based = false, plastic = false, weak_bonds = false, partitioned = false, surface = false;
  constexpr bool operator()(FieldWhen w) const {
    return w == kForAll || (w == kForStateBased && state_based) || (w == kForPlastic && plastic) ||
           (w == kForWeakBonds && weak_bonds) || (w == kForSurface && surface) ||
           (w == kForPartitioned && partitioned);
  }
};

#define PD_FIELD_BYTES_OF(name, Type, length, when, ...) \
  +(length == kWanted && needs(when) ? double(sizeof(Type)) : 0.0)
template <FieldLength kWanted>
constexpr double field_bytes(FieldNeeds needs) {
  return 0.0 PD_STATE_FIELDS(PD_FIELD_BYTES_OF);
}
#undef PD_FIELD_BYTES_OF

}  // namespace pd
