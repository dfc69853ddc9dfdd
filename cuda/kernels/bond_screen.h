// Screened force passes (bench/NOTES.md, "Forces without the breaking path"): `springforces`
// has two forms of each kernel, compiled apart so that neither carries the other's code in its
// loop. The breaking pass tests every bond against its limit and removes the bonds that break;
// the screened pass sums the forces with no breaking path, tracks the nearest any bond came to
// breaking at the particle's own end, and where that test does not rule a break out runs the
// breaking pass for the particle from the start. The engine launches the screened pass while no
// bond has broken for a while (kScreenHoldPasses) and the breaking pass otherwise: both give the
// same bits, so the choice changes only the speed.
#pragma once

#include <cmath>

#include "cuda/team.h"
#include "cuda/views.h"

namespace pd {

// Flag (Exec::flag) raised by a force pass in which some bond broke: one per parity of the
// pass's count, so the host reads one pass's flag while the next pass may raise the other.
constexpr int kFlagBroke = 3;
constexpr int kBrokeFlags = 2;

// Force passes run with the breaking pass after a pass in which some bond broke.
constexpr int kScreenHoldPasses = 64;

// Whether a bond of the particle may break, from the largest over its bonds of the own-end
// margin x - w L (x: the bond's stretch or Chen's extension, L: the particle's own limit, w
// the bond's strength), or of x alone without weakened bonds (w = 1: the breaking test's
// x > L exactly). With w, the breaking test compares x with w L rounded, which can be below
// w L by half an ulp; the margin here may be fused (one rounding), so a break leaves it above
// -|L| 2^-24, and the test keeps every margin above -|L| 2^-20.
template <bool kWeak>
PD_HD inline bool may_break(real nearest, real limit) {
  if constexpr (kWeak)
    return nearest > -std::fabs(limit) * real(0x1p-20);
  else
    return nearest > limit;
}

// Where a breaking pass raises `broke`: in its breaking branch, or after its loop where the
// particle has fewer intact bonds than the last pass left. Each form changes the compiler's code
// of the loop; the faster for each kernel, measured on the H100 (bench/NOTES.md): in the branch
// for the plain bond-based and state-based kernels (after the loop the bond-based one took 56
// registers and ran 12% slower, the plastic one 7%), after the loop where bonds may be weakened
// (in the branch: 6% slower).
template <bool kWeak>
constexpr bool kRaiseInBranch = !kWeak;

// The results of a force pass for particle i: its force, least stretch and intact bonds; raises
// `broke` (where not null) where the particle has fewer intact bonds than the last pass left. A
// team's leader writes the team's sums.
template <int kThreads = 1>
PD_HD inline void write_bond_forces(int32_t i, const ParticlesView& p, Vec3 force, real smin, int32_t intact,
                                    int32_t* broke, const Team<kThreads>& team = {}) {
  if (!team.leader()) return;
  if (broke && intact < p.intact[i]) raise_flag(broke);
  p.force[i] = force;
  p.strain_min[i] = intact > 0 ? smin : real(0);
  p.intact[i] = intact;
}

// The energy a force pass's broken bonds released, added to the particle's ledger: bond by bond by
// one thread per particle (the order of the sums as before teams), or summed per lane and added
// once by a team's leader (settle, which every lane calls).
template <int kThreads>
struct ReleasedEnergy {
  double lane_sum = 0;
  PD_HD void add(const ParticlesView& p, int32_t i, double energy) {
    if constexpr (kThreads == 1)
      p.ledger[i].released += energy;
    else
      lane_sum += energy;
  }
  PD_HD void settle(const ParticlesView& p, int32_t i, const Team<kThreads>& team) const {
    if constexpr (kThreads > 1) {
      const double total = team.sum(lane_sum);
      if (team.leader() && total != 0) p.ledger[i].released += total;
    }
  }
};

}  // namespace pd
