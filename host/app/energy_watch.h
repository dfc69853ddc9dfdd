// Energy bookkeeping of a run: the per-frame energy.csv log and the blow-up watchdog.
#pragma once

#include <cstdint>
#include <string>

#include "cuda/engine/engine.h"
#include "host/io/csv_log.h"

namespace pd {

// energy.csv, rewritten atomically after every frame.
class EnergyLog {
 public:
  explicit EnergyLog(std::string path);
  void add(int64_t frame, int64_t step, double time, const Energy& e);
  const std::string& text() const { return log_.text(); }
  // Continues a resumed run's log from its checkpointed text (rewritten at the next add).
  void restore(std::string text) { log_.restore(std::move(text)); }

 private:
  CsvLog log_;
};

// The energy watchdog: the balance (mechanical energy + released - work) may drift by the
// integrator's and the fracture's errors, a fraction of the energy the run started with and
// exchanged; a blow-up creates energy without bound. Returns the growth of the balance over that
// energy (> 1: blow-up).
double energy_excess(const Energy& e0, const Energy& e);

// The particle moving fastest: where a blow-up shows first.
int64_t fastest_particle(Engine& engine);

}  // namespace pd
