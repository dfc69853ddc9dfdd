#include "cuda/engine/memory_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include "cuda/state_fields.h"

namespace pd {

namespace {

// A cap in MiB from the environment, or `fallback`; a value that is not a finite number of MiB
// from 0 is an error naming the variable (std::invalid_argument).
size_t capped(const char* variable, size_t bytes) {
  const char* v = std::getenv(variable);
  if (!v || !*v) return bytes;
  char* end = nullptr;
  const double mb = std::strtod(v, &end);
  if (*end != '\0' || !(mb >= 0) || !(mb < 1e12))
    throw std::invalid_argument(std::string(variable) + ": '" + v +
                                "' is not allowed (allowed: a number of MiB from 0, below 1e12)");
  return std::min(bytes, size_t(mb * 1024 * 1024));
}

// Per particle, beyond the state table's arrays (cuda/state_fields.h, a state-based run's): the
// contact hash (keys, ids, sorted copies: 16 B; sorted records: 16 B; bins: up to 4 per particle
// x 8 B), the contact lists (origin 16 B, length 4 B, room for 8 partners of 4 B), their
// relisting (a particle's latest node and last round: 8 B), the slice bookkeeping and the bond
// loops' balanced launch order (4 B; bond_threads.h).
constexpr double kEngineParticleBytes =
    field_bytes<kParticles>(FieldNeeds{true, false, false}) + 16 + 16 + 32 + 16 + 4 + 32 + 8 + 8 + 4;
// Sliced-ELL padding: slices of 32 particles are as long as their longest family.
constexpr double kEllPadding = 1.15;

}  // namespace

size_t host_available_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  size_t kib = 0;
  for (std::string key; meminfo >> key;) {
    size_t value = 0;
    std::string unit;
    meminfo >> value >> unit;
    if (key == "MemAvailable:") {
      kib = value;
      break;
    }
  }
  return capped("PERIFRAC_HOST_MEMORY_MB", kib * 1024);
}

size_t backend_available_bytes(Backend b) {
  if (b == Backend::kCpu) return host_available_bytes();
  return capped("PERIFRAC_DEVICE_MEMORY_MB", cuda_free_bytes());
}

double bonds_per_particle(double horizon_ratio) {
  const double r = horizon_ratio + 0.5;
  return 4.0 / 3.0 * M_PI * r * r * r;
}

double engine_bytes_per_particle(double horizon_ratio, bool plastic, bool surface) {
  const double bonds = bonds_per_particle(horizon_ratio);
  // Lattice families: a stencil id (2 B) and the present, intact and (with weakened bonds) weak
  // bits, in 32-bit words.
  const double lattice = 2 + 3 * 4 * std::ceil(bonds / 32);
  return kEngineParticleBytes + lattice +
         bonds * kEllPadding * field_bytes<kSlots>(FieldNeeds{true, plastic, false, false, surface});
}

std::string format_bytes(double bytes) {
  char buf[32];
  if (bytes >= 1024.0 * 1024 * 1024)
    std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1024.0 * 1024 * 1024));
  else
    std::snprintf(buf, sizeof buf, "%.0f MiB", bytes / (1024.0 * 1024));
  return buf;
}

ParticleBudget particle_budget(Backend b, double horizon_ratio, bool plastic, bool surface, int ranks,
                               int ranks_per_host) {
  // Engine bytes per particle of the whole run, on one rank's backend.
  const double share = ranks > 1 ? kRankGhostAllowance / double(ranks) : 1.0;
  const double engine = engine_bytes_per_particle(horizon_ratio, plastic, surface) * share;
  const double host_free = double(host_available_bytes());
  const double host_per =
      double(std::max(ranks_per_host, 1)) * (kHostBytesPerParticle + (b == Backend::kCpu ? engine : 0));
  ParticleBudget budget;
  budget.max_particles = int64_t(host_free / host_per);
  budget.why = "what fits in the " + format_bytes(host_free) + " of free host memory at ~" +
               std::to_string(int64_t(host_per)) + " B per particle";
  if (b == Backend::kCuda) {
    const double device_free = double(backend_available_bytes(b));
    const int64_t on_device = int64_t(device_free / engine);
    if (on_device < budget.max_particles) {
      budget.max_particles = on_device;
      budget.why = "what fits in the " + format_bytes(device_free) + " free on the GPU at ~" +
                   std::to_string(int64_t(engine)) + " B per particle";
    }
  }
  char ratio[32];
  std::snprintf(ratio, sizeof ratio, "%g", horizon_ratio);
  budget.why += std::string(" (horizon ") + ratio + " spacings" + (plastic ? ", plastic" : "") +
                (ranks > 1 ? ", split over " + std::to_string(ranks) + " ranks" : "") + ")";
  return budget;
}

}  // namespace pd
