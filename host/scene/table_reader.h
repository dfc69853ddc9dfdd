// Typed, validated access to a scene file's TOML tables, and the one-line messages of its
// mistakes: "<file>: <key>: <what is wrong> (allowed: <what is allowed>)" (SceneError). The scene
// loader (scene_loader.cpp) reads every section through it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "host/scene/scene.h"
#include "host/scene/toml_include.h"

namespace pd {

using Keys = std::vector<std::string_view>;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Message helpers ---------------------------------------------------------------------------

// Replaces control characters (a quoted TOML key may hold a newline) so messages stay on one line.
std::string one_line(std::string_view s);
// `s` in double quotes, on one line.
std::string in_quotes(std::string_view s);
// "a, b, c", each item optionally quoted.
std::string join(const Keys& items, bool quote);
// Shortest decimal form that reads back as the same double ("0.5", "1e+08", "0.99999999").
std::string number_text(double v);
// "a table", "an integer", ... for messages.
std::string type_name(const toml::node& n);
// Throws SceneError(file, key, "what (allowed: allowed)"), each part on one line.
[[noreturn]] void scene_error(const std::string& file, const std::string& key, const std::string& what,
                              const std::string& allowed);

// ---- Numbers -----------------------------------------------------------------------------------

// A bound for a message: number_text, but a computed bound within round-off of a short decimal
// (0.1 / 10 = 0.010000000000000002) as that decimal.
std::string bound_text(double v);

// Allowed range of a float key; describe() is the "allowed" part of its messages.
struct Bounds {
  double lo = -kInf, hi = kInf;
  bool lo_open = false, hi_open = false;
  std::string note;  // appended to describe(), e.g. the meaning of the bound

  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi); }
  std::string describe() const {
    std::string s;
    if (lo == -kInf && hi == kInf) {
      s = "a finite number";
    } else if (hi == kInf) {
      s = std::string("a number ") + (lo_open ? "> " : ">= ") + bound_text(lo);
    } else {
      s = std::string("a number in ") + (lo_open ? "(" : "[") + bound_text(lo) + ", " + bound_text(hi) +
          (hi_open ? ")" : "]");
    }
    return note.empty() ? s : note[0] == '(' ? s + " " + note : s + ": " + note;
  }
};

Bounds greater_than(double lo);
Bounds at_least(double lo);
Bounds in_closed(double lo, double hi);
Bounds in_open(double lo, double hi);

// An integer or float node as a finite double within `bounds`.
double to_number(const toml::node& n, const std::string& file, const std::string& key, const Bounds& bounds);

// ---- Table reader ------------------------------------------------------------------------------

enum class Presence { optional, required };

// Typed access to one TOML table whose dotted path is `prefix`. The constructor rejects keys
// not in `allowed`, so a misspelt key is reported as unknown rather than as missing. The
// getters write `out` and return true when the key is present, leave `out` (the default) alone
// and return false when it is absent, and throw when it is required and absent.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string prefix, const std::string& file, const Keys& allowed)
      : table_(&table), prefix_(std::move(prefix)), file_(&file) {
    for (auto&& [key, value] : table) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end())
        fail(key.str(), "unknown key", join(allowed, false));
    }
  }

  // Dotted path of `key` in this table; the table's own path for an empty key.
  std::string path(std::string_view key) const {
    if (key.empty()) return prefix_;
    return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
  }

  [[noreturn]] void fail(std::string_view key, const std::string& what, const std::string& allowed) const {
    scene_error(*file_, path(key), what, allowed);
  }

  bool number(std::string_view key, double& out, const Bounds& bounds = {},
              Presence presence = Presence::optional) const {
    const toml::node* n = find(key, presence, bounds.describe());
    if (n) out = to_number(*n, *file_, path(key), bounds);
    return n != nullptr;
  }

  bool integer(std::string_view key, int64_t& out, int64_t min,
               int64_t max = std::numeric_limits<int64_t>::max()) const {
    const std::string allowed = max == std::numeric_limits<int64_t>::max()
                                    ? "an integer >= " + std::to_string(min)
                                    : "an integer from " + std::to_string(min) + " to " + std::to_string(max);
    const toml::node* n = find(key, Presence::optional, allowed);
    if (!n) return false;
    const auto* i = n->as_integer();
    if (!i) fail(key, "expected an integer, got " + type_name(*n), allowed);
    if (i->get() < min || i->get() > max) fail(key, std::to_string(i->get()) + " is out of range", allowed);
    out = i->get();
    return true;
  }

  bool boolean(std::string_view key, bool& out) const {
    const toml::node* n = find(key, Presence::optional, "true or false");
    if (!n) return false;
    const auto* b = n->as_boolean();
    if (!b) fail(key, "expected a boolean, got " + type_name(*n), "true or false");
    out = b->get();
    return true;
  }

  // A string; when `choices` is not empty it must be one of them.
  bool string(std::string_view key, std::string& out, const Keys& choices = {},
              Presence presence = Presence::optional) const {
    const std::string allowed = choices.empty() ? "a string" : join(choices, true);
    const toml::node* n = find(key, presence, allowed);
    if (!n) return false;
    const auto* s = n->as_string();
    if (!s) fail(key, "expected a string, got " + type_name(*n), allowed);
    if (!choices.empty() && std::find(choices.begin(), choices.end(), s->get()) == choices.end())
      fail(key, "unsupported value " + in_quotes(s->get()), allowed);
    out = s->get();
    return true;
  }

  // An array of exactly 3 finite numbers.
  bool vec3(std::string_view key, Vec3d& out, Presence presence = Presence::optional) const {
    const std::string allowed = "an array of 3 finite numbers [x, y, z]";
    const toml::node* n = find(key, presence, allowed);
    if (!n) return false;
    const auto* a = n->as_array();
    if (!a) fail(key, "expected an array of 3 numbers, got " + type_name(*n), allowed);
    if (a->size() != 3) fail(key, "expected 3 numbers, got " + std::to_string(a->size()), allowed);
    for (size_t c = 0; c < 3; ++c)
      out[c] = to_number(*a->get(c), *file_, path(key) + "[" + std::to_string(c) + "]", Bounds{});
    return true;
  }

  // Keyframes [[t, x, y, z], ...]: at least two, times >= 0 and strictly increasing.
  bool keyframes(std::string_view key, std::vector<SceneKeyframe>& out) const {
    const std::string allowed = "an array of at least 2 keyframes [time, x, y, z], times >= 0 and increasing";
    const toml::node* n = find(key, Presence::optional, allowed);
    if (!n) return false;
    const auto* a = n->as_array();
    if (!a) fail(key, "expected an array of keyframes, got " + type_name(*n), allowed);
    if (a->size() < 2) fail(key, std::to_string(a->size()) + " keyframe(s)", allowed);
    out.clear();
    for (size_t k = 0; k < a->size(); ++k) {
      const std::string item = path(key) + "[" + std::to_string(k) + "]";
      const auto* frame = a->get(k)->as_array();
      if (!frame || frame->size() != 4) scene_error(*file_, item, "expected [time, x, y, z]", allowed);
      SceneKeyframe f{};
      for (size_t c = 0; c < 4; ++c)
        f[c] = to_number(*frame->get(c), *file_, item + "[" + std::to_string(c) + "]",
                         c == 0 ? at_least(0) : Bounds{});
      if (k > 0 && !(f[0] > out.back()[0]))
        scene_error(*file_, item + "[0]",
                    "time " + number_text(f[0]) + " does not follow " + number_text(out.back()[0]), allowed);
      out.push_back(f);
    }
    return true;
  }

  bool has(std::string_view key) const { return table_->get(key) != nullptr; }
  const toml::node* node(std::string_view key) const { return table_->get(key); }
  const std::string& file() const { return *file_; }
  bool is_string(std::string_view key) const {
    const toml::node* n = table_->get(key);
    return n && n->is_string();
  }

  // An array of `n` finite numbers.
  template <size_t N>
  bool numbers(std::string_view key, std::array<double, N>& out, const std::string& allowed) const {
    const toml::node* n = find(key, Presence::optional, allowed);
    if (!n) return false;
    const auto* a = n->as_array();
    if (!a)
      fail(key, "expected an array of " + std::to_string(N) + " numbers, got " + type_name(*n), allowed);
    if (a->size() != N)
      fail(key, "expected " + std::to_string(N) + " numbers, got " + std::to_string(a->size()), allowed);
    for (size_t c = 0; c < N; ++c)
      out[c] = to_number(*a->get(c), *file_, path(key) + "[" + std::to_string(c) + "]", Bounds{});
    return true;
  }

  // The sub-table `key` ([simulation], ...); an empty one when absent.
  TableReader table(std::string_view key, const Keys& allowed) const {
    return TableReader(sub_table(key), path(key), *file_, allowed);
  }

  // The entries of the sub-table `key`, each itself a table: [key.NAME] -> (NAME, reader).
  std::vector<std::pair<std::string, TableReader>> named_tables(std::string_view key,
                                                                const Keys& allowed) const {
    std::vector<std::pair<std::string, TableReader>> out;
    for (auto&& [name, value] : sub_table(key)) {
      const std::string name_path = path(key) + "." + std::string(name.str());
      if (!value.is_table())
        scene_error(*file_, name_path, "expected a table, got " + type_name(value),
                    "a [" + name_path + "] table");
      out.emplace_back(std::string(name.str()), TableReader(*value.as_table(), name_path, *file_, allowed));
    }
    return out;
  }

  // The elements of the array of tables `key` ([[key]]); none when absent.
  std::vector<TableReader> table_array(std::string_view key, const Keys& allowed) const {
    const std::string kind = "[[" + path(key) + "]] tables";
    const toml::node* n = table_->get(key);
    if (!n) return {};
    const auto* a = n->as_array();
    if (!a) fail(key, "expected an array of tables, got " + type_name(*n), kind);
    std::vector<TableReader> out;
    for (size_t i = 0; i < a->size(); ++i) {
      const std::string element_path = path(key) + "[" + std::to_string(i) + "]";
      const toml::node& element = *a->get(i);
      if (!element.is_table())
        scene_error(*file_, element_path, "expected a table, got " + type_name(element), kind);
      out.emplace_back(*element.as_table(), element_path, *file_, allowed);
    }
    return out;
  }

 private:
  const toml::node* find(std::string_view key, Presence presence, const std::string& allowed) const {
    const toml::node* n = table_->get(key);
    if (!n && presence == Presence::required) fail(key, "missing required key", allowed);
    return n;
  }

  const toml::table& sub_table(std::string_view key) const {
    static const toml::table kEmpty;
    const toml::node* n = table_->get(key);
    if (!n) return kEmpty;
    if (!n->is_table()) fail(key, "expected a table, got " + type_name(*n), "a [" + path(key) + "] table");
    return *n->as_table();
  }

  const toml::table* table_;
  std::string prefix_;
  const std::string* file_;
};

}  // namespace pd
