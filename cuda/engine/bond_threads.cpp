#include "cuda/engine/bond_threads.h"

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>

#include "cuda/engine/lattice_families.h"
#include "cuda/team.h"
#include "cuda/views.h"

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

// Whether most of the run's particles are mesh-filled. Box grids count as regular with explicit
// families too (--explicit-families): their families are as even as the lattice's, and one thread
// per particle beats 4 lanes there by 10-14% at 1M.
static bool mesh_filled(const SimulationInput& in) {
  const int64_t n = int64_t(in.particles.size());
  return 2 * (n - box_grid_particles(in.particles)) > n;
}

int bond_threads_of(const SimulationInput& in) {
  const int requested = requested_bond_threads(in);
  if (requested > 0) return requested;
  return bond_threads_for(int64_t(in.particles.size()), mesh_filled(in), 0);
}

int requested_team_block() {
  const char* v = std::getenv("PERIFRAC_TEAM_BLOCK");
  if (!v || !*v) return 0;
  const std::string s = v;
  if (s != "0" && s != "128" && s != "256")
    throw std::invalid_argument("environment PERIFRAC_TEAM_BLOCK='" + s +
                                "': allowed are 128, 256 (threads per block) and 0 (chosen from the scene)");
  return std::atoi(v);
}

int team_block_of(const SimulationInput& in, bool state_based, double mean_bonds, int lanes) {
  const int requested = requested_team_block();
  if (requested > 0) return requested;
  return team_block_for(mesh_filled(in), state_based, mean_bonds / std::max(lanes, 1), 0);
}

std::vector<int32_t> balanced_particle_order(const std::vector<int32_t>& count, int window) {
  if (window <= 1) return {};
  std::vector<int32_t> order(count.size());
  std::iota(order.begin(), order.end(), 0);
  for (size_t first = 0; first < order.size(); first += size_t(window)) {
    const auto end = order.begin() + std::min(order.size(), first + size_t(window));
    std::stable_sort(order.begin() + first, end, [&](int32_t a, int32_t b) { return count[a] > count[b]; });
  }
  return order;
}

int balance_window() {
  const char* v = std::getenv("PERIFRAC_BALANCE_WINDOW");
  if (!v || !*v) return kSliceWidth;
  const std::string s = v;
  const bool digits = s.size() <= 7 && s.find_first_not_of("0123456789") == std::string::npos;
  if (!digits)
    throw std::invalid_argument("environment PERIFRAC_BALANCE_WINDOW='" + s +
                                "': allowed is a count of particles, 0 to 9999999 (0 or 1: off)");
  return std::atoi(v);
}

}  // namespace pd
