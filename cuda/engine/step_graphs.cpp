#include "cuda/engine/step_graphs.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pd {

StepGraphs requested_step_graphs(const SimulationInput& in) {
  if (in.step_graphs != StepGraphs::kAuto) return in.step_graphs;
  const char* v = std::getenv("PERIFRAC_STEP_GRAPHS");
  if (!v || !*v) return StepGraphs::kAuto;
  const std::string s = v;
  if (s == "auto") return StepGraphs::kAuto;
  if (s == "on") return StepGraphs::kOn;
  if (s == "off") return StepGraphs::kOff;
  throw std::invalid_argument("environment PERIFRAC_STEP_GRAPHS='" + s +
                              "': allowed are auto (graphs of the step in scenes below " +
                              std::to_string(kGraphParticles) + " particles), on and off");
}

bool step_graphs_wanted(const SimulationInput& in) {
  switch (requested_step_graphs(in)) {
    case StepGraphs::kOn:
      return true;
    case StepGraphs::kOff:
      return false;
    case StepGraphs::kAuto:
      break;
  }
  return int64_t(in.particles.size()) < kGraphParticles;
}

bool overlapped_launches_wanted() {
  const char* v = std::getenv("PERIFRAC_OVERLAP_LAUNCHES");
  if (!v || !*v) return true;
  const std::string s = v;
  if (s == "on") return true;
  if (s == "off") return false;
  throw std::invalid_argument(
      "environment PERIFRAC_OVERLAP_LAUNCHES='" + s +
      "': allowed are on (a launch overlaps the last blocks of the one before it) and off");
}

}  // namespace pd
