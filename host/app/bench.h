// `perifrac bench`: times the step kernels on a scene or a synthetic lattice and prints
// bond-updates per second per kernel and per step, with registers and occupancy; results
// go to bench/results/ as JSON and CSV with the device, date and git revision.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pd {

struct BenchOptions {
  std::string scene;                   // a scene file, or empty for the lattice
  std::vector<std::string> overrides;  // --set KEY=VALUE, applied to the scene file
  double scale = 1.0;                  // scene particle-count scale
  int64_t lattice = 100;               // particles per side of the synthetic cube
  double horizon = 3.0;                // delta / lambda of the lattice
  bool contact = false;                // lattice: launch collection + collisions
  bool explicit_families = false;      // box-grid bodies read partner indices as other bodies do
  std::string screen = "auto";         // springforces: auto | off | always (cuda/kernels/bond_screen.h)
  int bond_threads = 0;                // threads per particle in the GPU's bond loops: 0 (auto), 1 .. 32
  std::string step_graphs = "auto";    // the step as CUDA graphs: auto | on | off (cuda/engine/step_graphs.h)
  std::string contact_rebuild = "incremental";  // contact lists: incremental | full (contact_relist.h)
  std::string model = "bond_based";             // lattice material: bond_based | state_based | plastic
  std::string backend = "auto";
  int64_t steps = 200;
  int64_t warmup = 20;
  bool allow_unstable_dt = false;  // time a dt past the stable step (refused otherwise, as by run)
  std::string out = "bench/results";
};

int bench_command(const BenchOptions& options);

}  // namespace pd
