// How a run rebuilds its contact lists (ContactRebuild, particle_set.h).
#pragma once

#include "cuda/engine/particle_set.h"

namespace pd {

// What a run of `in` asks for: in.contact_rebuild where it is kFull, else the environment's
// PERIFRAC_CONTACT_REBUILD (incremental or full), else kIncremental. std::invalid_argument names
// a bad value.
ContactRebuild requested_contact_rebuild(const SimulationInput& in);

}  // namespace pd
