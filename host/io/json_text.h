// Text for a JSON string value: quotes and backslashes escaped, control characters as \u00XX
// (RFC 8259, section 7), everything else as it is (UTF-8 passes through).
#pragma once

#include <cstdio>
#include <string>

namespace pd {

inline std::string json_escape(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char code[8];
      std::snprintf(code, sizeof(code), "\\u%04x", unsigned(static_cast<unsigned char>(c)));
      o += code;
    } else {
      o += c;
    }
  }
  return o;
}

}  // namespace pd
