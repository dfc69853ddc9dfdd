// How many threads of the GPU's bond loops share one particle (cuda/team.h), chosen once per run
// from the scene: a function of the whole run's particles only, so every rank of a partitioned
// run sums a particle's bonds in the same order as one rank.
#pragma once

#include "cuda/engine/particle_set.h"

namespace pd {

// The threads per particle a run of `in` asks for: in.bond_threads where set, else the
// environment's PERIFRAC_BOND_THREADS (1, 4, 8, 16 or 32: e.g. 1 to reproduce a run's bits
// from before teams), else 0 (chosen from the scene). std::invalid_argument names a bad value.
int requested_bond_threads(const SimulationInput& in);

// The threads per particle the run of `in` uses: the request, else bond_threads_for from its
// particle count and whether most of its particles are mesh-filled (not in box-grid bodies, whose
// families are even whether read by lattice offset or from explicit lists).
int bond_threads_of(const SimulationInput& in);

}  // namespace pd
