// Compile-time feature sets (LAMMPS KOKKOS style): the per-step kernels are instantiated for
// the physics a run uses, so an elastic scene pays nothing for plasticity or anisotropy and a
// bond-based one nothing for dilatation. The engine picks the instantiation once per call.
#pragma once

#include <type_traits>

#include "views.h"

namespace pd {

// The physics of a run.
struct KernelFeatures {
  bool contact = false;          // contact lists and collisions
  bool state_based = false;      // some material is state-based: dilatation in `init`
  bool plastic = false;          // some state-based material is plastic
  bool anisotropic = false;      // some state-based material has an anisotropy matrix G
  bool weak_bonds = false;       // some bonds carry a strength factor (pre-cracks and weakening)
  bool surface = false;          // some bond-based material has the surface correction
  bool surface_factors = false;  // some material has it (the factors are made at set-up)
  bool ghosts = false;           // some material has the ghost surface correction
  bool lattice = false;          // some bodies have lattice families (host/lattice_families.h)
  bool lattice_listed = false;   // ... whose partners are read from the lists (a partitioned rank)
};

// How a kernel walks lattice families, fixed at compile time so that a run pays only for the
// form it uses: none (every family from its list), partners at the stencil entries' offsets (one
// rank: indices are the lattice's), or at the offsets unless the particle's stencil is `listed`
// (a partitioned rank, whose own particles near its boundary read partners from their lists;
// also the kernels off the step's hot path, which serve both).
enum LatticeMode : int { kNoLattice = 0, kLatticeOffsets = 1, kLatticeListed = 2 };

constexpr int lattice_mode(bool lattice, bool listed) {
  return lattice ? (listed ? kLatticeListed : kLatticeOffsets) : kNoLattice;
}

inline KernelFeatures features_of(const MaterialTable& mt, bool contact) {
  KernelFeatures f;
  f.contact = contact;
  for (int k = 0; k < mt.count; ++k) {
    const Material& m = mt.m[k];
    f.surface_factors = f.surface_factors || m.surface_correction;
    f.ghosts = f.ghosts || m.ghost_correction;
    if (m.model != kStateBased) {
      f.surface = f.surface || m.surface_correction;
      continue;
    }
    f.state_based = true;
    f.plastic = f.plastic || m.plastic;
    f.anisotropic = f.anisotropic || m.anisotropic;
  }
  return f;
}

// What the integration kernels take on from their neighbours in the step (integrate_fused.h):
// `init`, the bond-based init after the position update (no state-based material: its init
// reads the partners' new positions); `gravity`, gravity alone before the velocity update (no
// projectiles or colliders); `steps_meet`, a step's velocity update in one pass with the next
// step's position update (nothing on the host between them: no scripted motion, free bodies or
// moving colliders). Each gives the same bits as the kernels apart.
struct IntegrationFusion {
  bool init = false, gravity = false, steps_meet = false;
};

// Calls f(std::integral_constant<bool, b>...) with the runtime flags turned into types, so
// one call site reaches every instantiation: static_bools(f, true, false) calls
// f(std::true_type{}, std::false_type{}).
template <bool... kDone, class F>
void static_bools(F&& f) {
  f(std::integral_constant<bool, kDone>{}...);
}
template <bool... kDone, class F, class... Rest>
void static_bools(F&& f, bool first, Rest... rest) {
  if (first)
    static_bools<kDone..., true>(f, rest...);
  else
    static_bools<kDone..., false>(f, rest...);
}

}  // namespace pd
