#include "cuda/engine/bond_threads.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "cuda/engine/lattice_families.h"
#include "cuda/team.h"

namespace pd {

int requested_bond_threads(const SimulationInput& in) {
  if (in.bond_threads > 0) return in.bond_threads;
  const char* v = std::getenv("PERIFRAC_BOND_THREADS");
  if (!v || !*v) return 0;
  const std::string s = v;
  const bool digits = s.size() <= 2 && s.find_first_not_of("0123456789") == std::string::npos;
  const int threads = digits ? std::atoi(v) : -1;
  if (threads != 0 && !valid_bond_threads(threads))
    throw std::invalid_argument(
        "environment PERIFRAC_BOND_THREADS='" + s +
        "': allowed are 1, 4, 8, 16, 32 (threads per particle) and 0 (chosen from the scene)");
  return threads;
}

int bond_threads_of(const SimulationInput& in) {
  const int requested = requested_bond_threads(in);
  if (requested > 0) return requested;
  const int64_t n = int64_t(in.particles.size());
  // Box grids count as regular with explicit families too (--explicit-families): their families
  // are as even as the lattice's, and one thread per particle beats 4 lanes there by 10-14% at 1M.
  const int64_t regular = box_grid_particles(in.particles);
  return bond_threads_for(n, 2 * (n - regular) > n, 0);
}

}  // namespace pd
