// A scene file's text as a TOML document (toml_document.h).
#include "host/scene/toml_document.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "host/scene/scene.h"
#include "host/scene/table_reader.h"

namespace pd {
namespace {

// The location takes the place of the file name: "<file>:<line>:<column>: TOML syntax error: ...".
SceneError syntax_error(const std::string& path, int64_t line, int64_t column, std::string_view description) {
  return SceneError(path + ":" + std::to_string(line) + ":" + std::to_string(column), "",
                    "TOML syntax error: " + one_line(description));
}

// toml++ 3.3 decides whether a non-ASCII character is whitespace with a table that falls through
// to __builtin_unreachable() for most of U+00A1..U+0499, U+2FF6..U+33EF and U+FB0A..U+FEFE
// (upstream issues #190 and #295): undefined behaviour whenever the parser asks, which it does
// for any character outside a string and, in some places, inside one. parse_toml_document therefore hands
// toml++ the text with each such character c replaced by the private-use character U+F0000 + c,
// which the table handles, and maps keys, strings and messages back after parsing.
constexpr char32_t kShift = 0xF0000;

bool breaks_toml_whitespace_table(char32_t c) {
  if (c <= 0xA0 || c >= 0xFEFF || c == 0x3000) return false;
  const char32_t block = (c - 0xA0) / 0x3FA;
  return block == 0 || block == 11 || block == 63;
}

// Decodes the UTF-8 sequence at text[i] into `c` and returns its length; 0 when it is malformed.
size_t decode_utf8(std::string_view text, size_t i, char32_t& c) {
  const auto lead = static_cast<unsigned char>(text[i]);
  const size_t length = lead < 0x80 ? 1 : lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 0;
  if (length == 0 || i + length > text.size()) return 0;
  c = length == 1 ? lead : lead & (0x7F >> length);
  for (size_t k = 1; k < length; ++k) {
    const auto next = static_cast<unsigned char>(text[i + k]);
    if ((next & 0xC0) != 0x80) return 0;
    c = (c << 6) | (next & 0x3F);
  }
  const char32_t shortest[] = {0, 0, 0x80, 0x800, 0x10000};  // overlong encodings are malformed
  return c >= shortest[length] ? length : 0;
}

void append_utf8(std::string& out, char32_t c) {
  if (c < 0x80) {
    out += char(c);
  } else if (c < 0x800) {
    out += char(0xC0 | (c >> 6));
    out += char(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += char(0xE0 | (c >> 12));
    out += char(0x80 | ((c >> 6) & 0x3F));
    out += char(0x80 | (c & 0x3F));
  } else {
    out += char(0xF0 | (c >> 18));
    out += char(0x80 | ((c >> 12) & 0x3F));
    out += char(0x80 | ((c >> 6) & 0x3F));
    out += char(0x80 | (c & 0x3F));
  }
}

// `text` with each character c that breaks the table replaced by U+F0000 + c (forward) or each
// U+F0000 + c by c (back). Malformed UTF-8 is copied as it is: toml++ refuses it before asking.
std::string shift_characters(std::string_view text, bool forward) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    char32_t c = 0;
    const size_t length = decode_utf8(text, i, c);
    if (length == 0) {
      out += text[i++];
      continue;
    }
    if (forward && breaks_toml_whitespace_table(c)) {
      append_utf8(out, kShift + c);
    } else if (!forward && c > kShift && breaks_toml_whitespace_table(c - kShift)) {
      append_utf8(out, c - kShift);
    } else {
      out.append(text, i, length);
    }
    i += length;
  }
  return out;
}

// The document with shift_characters(..., back) applied to every key and string.
toml::array shift_back(const toml::array& array);
toml::table shift_back(const toml::table& table) {
  toml::table out;
  for (auto&& [key, node] : table) {
    const std::string name = shift_characters(key.str(), false);
    if (const auto* s = node.as_string()) {
      out.insert(name, shift_characters(s->get(), false));
    } else if (const auto* t = node.as_table()) {
      out.insert(name, shift_back(*t));
    } else if (const auto* a = node.as_array()) {
      out.insert(name, shift_back(*a));
    } else {
      node.visit([&](const auto& value) { out.insert(name, value); });
    }
  }
  return out;
}
toml::array shift_back(const toml::array& array) {
  toml::array out;
  for (const toml::node& node : array) {
    if (const auto* s = node.as_string()) {
      out.push_back(shift_characters(s->get(), false));
    } else if (const auto* t = node.as_table()) {
      out.push_back(shift_back(*t));
    } else if (const auto* a = node.as_array()) {
      out.push_back(shift_back(*a));
    } else {
      node.visit([&](const auto& value) { out.push_back(value); });
    }
  }
  return out;
}

}  // namespace

toml::table parse_toml_document(const std::string& text, const std::string& path) {
  // Characters that toml++ cannot classify go through the private-use plane 15 (see above); one
  // already there would come back as another character, so it is refused.
  const std::string shifted = shift_characters(text, true);
  const bool was_shifted = shifted != text;
  if (was_shifted && shift_characters(shifted, false) != text)
    scene_error(path, "", "the file holds private-use characters of U+F00A1..U+FFEFE",
                "no such characters (they stand in for others while the TOML parser reads the file)");
  toml::table root;
  try {
    root = toml::parse(shifted, path);
  } catch (const toml::parse_error& e) {
    const std::string description(e.description());
    throw syntax_error(path, e.source().begin.line, e.source().begin.column,
                       was_shifted ? shift_characters(description, false) : description);
  }
  return was_shifted ? shift_back(root) : root;
}

}  // namespace pd
