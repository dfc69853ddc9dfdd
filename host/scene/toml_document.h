// A scene file's text as a TOML document (toml++ 3.3), with the characters toml++ cannot classify
// carried through: their keys, strings and messages come back as written.
#pragma once

#include <string>

#include "host/scene/toml_include.h"

namespace pd {

// The document of `text` (read from `path`). Throws SceneError "<path>:<line>:<column>: TOML
// syntax error: ..." for a syntax error, and naming `path` for a private-use character of
// U+F00A1..U+FFEFE, which stands in for others while the parser reads.
toml::table parse_toml_document(const std::string& text, const std::string& path);

}  // namespace pd
