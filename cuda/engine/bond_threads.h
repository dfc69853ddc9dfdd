// How many threads of the GPU's bond loops share one particle (cuda/team.h), chosen once per run
// from the scene: a function of the whole run's particles only, so every rank of a partitioned
// run sums a particle's bonds in the same order as one rank.
#pragma once

#include <cstdint>
#include <vector>

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

// The threads per block of the run's team launches: PERIFRAC_TEAM_BLOCK where set (128 or 256;
// 0: chosen), else team_block_for from whether most particles are mesh-filled, whether the run
// has state-based materials and its families' mean bond count over its `lanes` per particle.
// std::invalid_argument names a bad value.
int requested_team_block();
int team_block_of(const SimulationInput& in, bool state_based, double mean_bonds, int lanes);

// The order in which a team launch visits explicit families (ParticleRange::ids): within each
// window of `window` consecutive particles, longest family first (ties by index). A warp's time is
// its longest family's, so warps of like counts idle fewer lanes. The window is a slice of the
// families' slots (kSliceWidth particles, whose slots share 128-byte rows): wider windows scatter
// a warp's rows and partners and lose more than the lanes gain (bench/NOTES.md). Every particle's
// sums are its own, in its own order: the same bits in any order. window <= 1: none (empty).
std::vector<int32_t> balanced_particle_order(const std::vector<int32_t>& count, int window);

// The window the run's team launches use: PERIFRAC_BALANCE_WINDOW where set (0 or 1: off),
// else kSliceWidth. std::invalid_argument names a bad value.
int balance_window();

}  // namespace pd
