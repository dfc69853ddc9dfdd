#include "cuda/engine/contact_rebuild.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pd {

ContactRebuild requested_contact_rebuild(const SimulationInput& in) {
  if (in.contact_rebuild == ContactRebuild::kFull) return ContactRebuild::kFull;
  const char* v = std::getenv("PERIFRAC_CONTACT_REBUILD");
  if (!v || !*v) return ContactRebuild::kIncremental;
  const std::string s = v;
  if (s == "incremental") return ContactRebuild::kIncremental;
  if (s == "full") return ContactRebuild::kFull;
  throw std::invalid_argument("environment PERIFRAC_CONTACT_REBUILD='" + s +
                              "': allowed are incremental (the lists of the particles that left their "
                              "skins rebuilt alone where they are few) and full (every list at every build)");
}

}  // namespace pd
