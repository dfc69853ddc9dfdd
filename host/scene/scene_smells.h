// Scene smells: a scene that loads and runs but most likely not as meant. One warning line each,
// printed at start-up (the run goes on): an anchor whose box holds no particle, two bodies of one
// name, particles that start below the floor, bodies that overlap.
#pragma once

#include <string>
#include <vector>

#include "cuda/engine/particle_set.h"
#include "host/scene/scene.h"

namespace pd {

// The warnings for `scene` as set up in `in` (bodies named `body_names`), one line each,
// starting "warning: ".
std::vector<std::string> scene_smells(const Scene& scene, const SimulationInput& in,
                                      const std::vector<std::string>& body_names);

}  // namespace pd
