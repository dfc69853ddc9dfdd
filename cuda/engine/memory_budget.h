// How many particles fit: memory a run needs per particle on the host and on the engine's
// backend, and what the machine has free, so an oversized scene is refused before anything
// big is allocated (and not by an allocation failure or the OOM killer halfway through).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "cuda/engine/engine.h"

namespace pd {

// Not enough memory for the scene. The message names the need, what is free, and the remedy.
class ResourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Free memory for a run: the host's MemAvailable, or the GPU's free memory. The environment
// variables PERIFRAC_HOST_MEMORY_MB / PERIFRAC_DEVICE_MEMORY_MB cap them (tests, shared machines).
size_t host_available_bytes();
size_t backend_available_bytes(Backend b);

// Bonds of an interior particle of a grid with horizon delta = ratio * lambda, counting the
// neighbours that partial volumes reach (delta + lambda/2): the sphere's volume in cells.
double bonds_per_particle(double horizon_ratio);

// Engine memory per particle: the particle arrays, the collision hash and the bonds (4 B each,
// 12 B with a plastic history, 2 B more with the surface correction's factors).
double engine_bytes_per_particle(double horizon_ratio, bool plastic, bool surface);

// Host memory per particle while a scene is set up and run (particle set, geometry, outputs).
inline constexpr double kHostBytesPerParticle = 160;

struct ParticleBudget {
  int64_t max_particles = 0;
  std::string why;  // e.g. "what fits in the 12.3 GiB free on the GPU at ~900 B per particle"
};

// The largest particle count a run on `b` can hold, given the largest horizon ratio of its
// materials, whether any is plastic and whether any bond-based one has the surface correction; the
// CPU engine shares the host's memory. A run over
// `ranks` ranks (cuda/parallel/), `ranks_per_host` of them on this host: each rank's engine holds
// its share plus ghosts, every rank holds the whole particle set on the host while it sets up.
ParticleBudget particle_budget(Backend b, double horizon_ratio, bool plastic, bool surface, int ranks = 1,
                               int ranks_per_host = 1);

// The share of the particles a rank's engine holds, ghosts included, as the budget assumes it.
inline constexpr double kRankGhostAllowance = 1.15;

// "1.5 GiB", "320 MiB": for messages.
std::string format_bytes(double bytes);

}  // namespace pd
