// The table reader's messages and numbers (table_reader.h).
#include "host/scene/table_reader.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace pd {

// Replaces control characters (a quoted TOML key may hold a newline) so messages stay on one line.
std::string one_line(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(c));
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

std::string in_quotes(std::string_view s) {
  return "\"" + one_line(s) + "\"";
}

// "a, b, c", each item optionally quoted.
std::string join(const Keys& items, bool quote) {
  std::string out;
  for (std::string_view item : items) {
    if (!out.empty()) out += ", ";
    out += quote ? in_quotes(item) : std::string(item);
  }
  return out;
}

// Shortest decimal form that reads back as the same double ("0.5", "1e+08", "0.99999999").
std::string number_text(double v) {
  char buf[40];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string bound_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  const double shown = std::strtod(buf, nullptr);
  return std::abs(shown - v) <= 1e-12 * std::abs(v) ? std::string(buf) : number_text(v);
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::none:
      return "nothing";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
  }
  return "an unknown type";
}

[[noreturn]] void scene_error(const std::string& file, const std::string& key, const std::string& what,
                              const std::string& allowed) {
  throw SceneError(file, one_line(key), one_line(what) + " (allowed: " + one_line(allowed) + ")");
}

Bounds greater_than(double lo) {
  return {lo, kInf, true, false, ""};
}
Bounds at_least(double lo) {
  return {lo, kInf, false, false, ""};
}
Bounds in_closed(double lo, double hi) {
  return {lo, hi, false, false, ""};
}
Bounds in_open(double lo, double hi) {
  return {lo, hi, true, true, ""};
}

// An integer or float node as a finite double within `bounds`.
double to_number(const toml::node& n, const std::string& file, const std::string& key, const Bounds& bounds) {
  double v = 0;
  if (const auto* i = n.as_integer()) {
    v = static_cast<double>(i->get());
  } else if (const auto* f = n.as_floating_point()) {
    v = f->get();
  } else {
    scene_error(file, key, "expected a number, got " + type_name(n), bounds.describe());
  }
  if (!std::isfinite(v))
    scene_error(file, key, number_text(v) + " is not a finite number", bounds.describe());
  if (!bounds.contains(v)) scene_error(file, key, number_text(v) + " is out of range", bounds.describe());
  return v;
}

}  // namespace pd
