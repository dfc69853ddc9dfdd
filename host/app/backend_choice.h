// Picks the backend a command runs on: "cpu", "cuda", or "auto" (CUDA when a device answers).
#pragma once

#include <string>

#include "cuda/engine/engine.h"

namespace pd {

// Throws std::invalid_argument for an unknown name and std::runtime_error when "cuda" is
// asked for but unavailable. `note` says why "auto" chose what it chose.
Backend choose_backend(const std::string& name, std::string* note);

}  // namespace pd
