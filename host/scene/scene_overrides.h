// A scene's --set KEY=VALUE overrides, applied to its TOML document before it is read.
#pragma once

#include <string>

#include "host/scene/toml_include.h"

namespace pd {

// Applies one "KEY=VALUE" override to the document: tables on the way are created, an index one
// past the end of an array of tables (or 0 where there is none) adds an empty table to it, other
// array elements must exist; the value replaces what the file had.
// Throws SceneError naming "--set KEY" for a setting that is not KEY=VALUE, a value that is not
// TOML or a path that the document cannot hold.
void apply_override(toml::table& root, const std::string& setting, const std::string& file);

}  // namespace pd
