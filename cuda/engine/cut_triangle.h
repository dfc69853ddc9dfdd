// A triangle of a pre-crack or weakened surface, as the engine takes it (host/bond_cuts.h).
#pragma once

#include <array>
#include <cstdint>

namespace pd {

struct CutTriangle {
  std::array<std::array<double, 3>, 3> corner{};
  double strength = 0;  // 0: the bonds crossing are removed; in (0, 1): their strain limit is scaled
  int32_t body = -1;    // only bonds of this body; -1: every body
};

}  // namespace pd
