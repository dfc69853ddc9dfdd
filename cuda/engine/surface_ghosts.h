// Set-up of the ghost surface correction (cuda/kernels/surface_ghosts.h): which particles miss
// bonds of the interior's family, their ghosts, the fit's inverse and what the stable time step
// must take for them.
#pragma once

#include <cstdint>
#include <vector>

#include "cuda/engine/body_solids.h"
#include "cuda/engine/engine.h"
#include "cuda/kernels/surface_ghosts.h"

namespace pd {

// The stable step with ghosts over the step without them, at most: their bonds' forces reach the
// whole family through the fit's extrapolation (measured on lattice blocks at delta = 3 lambda,
// both models: 1 / 3.9 by the engine's estimate, 1 / 3.2 by the stiffness's largest eigenvalue
// in the static solver). The validation problems and the benchmarks take it on their continuum
// dt_c; `perifrac run` starts from it and then measures the step on its engine (stable_step.h).
constexpr double kGhostStableStepRatio = 0.25;

// The tables of GhostView on the host, and what the set-up found.
struct GhostTables {
  std::vector<int32_t> particle, of, first, receivers;
  std::vector<int32_t> push_first;  // each ghosted particle's bonds' rows of the push table (GhostView)
  std::vector<real> inverse, moment, inv_mw;
  std::vector<Vec4> offset;
  // Per particle, the ghost bonds' share of its stability rate (cuda/kernels/family.h
  // stability_rate's units: 1/s^2), added to the bonds' before the stable step is taken.
  std::vector<double> stability_rate;
  int64_t thin = 0;        // particles that miss bonds but whose family does not span the fit's basis
  int64_t precracked = 0;  // particles that lost bonds to the scene's cuts
  int64_t linear = 0;      // ghosted particles on the linear fit (surface_ghosts.cpp kMaxExtrapolation)
  int32_t size() const { return int32_t(particle.size()); }
};

// The ghosts of the particles of `ps` whose material asks for them (Material::ghost_correction),
// from their families `bonds` as built, before the scene's cuts; `cut_count` holds the families'
// sizes after them, and a particle that lost bonds to a cut gets no ghosts (a pre-crack is not
// a surface of the body, as for the factors: surface_correction.h). A stencil offset of the material's
// lattice (spacing lambda, out to its family radius) is missing where no partner lies within 0.75 lambda of
// it: exact on a grid, whose partners sit on the offsets and whose points outside the body lie a spacing or
// more from any particle; for scattered particles (tets, Voronoi cells) a stencil point is outside the body
// where `solids` knows the body's solid and the point lies outside it, else where no particle is near it.
GhostTables surface_ghosts(const ParticleSet& ps, const MaterialTable& mt, const BondLists& bonds,
                           const std::vector<int32_t>& cut_count, const BodySolids* solids = nullptr);

// The backend memory the tables take as the engine holds them (GhostView's arrays, this step's
// push table and a mirror row for each of the families' `slots` included). A body of many thin
// parts can have most particles ghosted, at ~2-4 KB each.
double ghost_table_bytes(const GhostTables& t, int64_t slots);

// Refuses the tables with a clear message (ResourceError) where `backend` has not the memory
// for them free, before they are allocated.
void check_ghost_memory(const GhostTables& t, int64_t slots, Backend backend);

}  // namespace pd
