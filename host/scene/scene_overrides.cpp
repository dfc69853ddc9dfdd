// --set overrides (scene_overrides.h).
#include "host/scene/scene_overrides.h"

#include <algorithm>

#include "host/scene/table_reader.h"

namespace pd {

void apply_override(toml::table& root, const std::string& setting, const std::string& file) {
  const std::string allowed =
      "KEY=VALUE, KEY a dotted path (materials.glass.density, bodies[0].spacing, materials.\"a.b\".density), "
      "VALUE a TOML value (2.5e9, \"text\", [1, 0, 0], true)";
  const size_t eq = setting.find('=');
  std::string key = eq == std::string::npos ? setting : setting.substr(0, eq);
  while (!key.empty() && (key.back() == ' ' || key.back() == '\t')) key.pop_back();
  key.erase(0, key.find_first_not_of(" \t"));
  auto fail = [&](const std::string& what) { scene_error(file, "--set " + key, what, allowed); };
  if (eq == std::string::npos || eq == 0) fail("expected KEY=VALUE");
  if (setting.find_first_of("\n\r") != std::string::npos)
    fail("it holds a line break (one KEY=VALUE per --set)");
  toml::table value_doc;
  try {
    value_doc = toml::parse("value = " + setting.substr(eq + 1));
  } catch (const toml::parse_error& e) {
    fail("the value is not TOML: " + std::string(e.description()));
  }
  // Walk the path: name segments, each optionally followed by [index] parts.
  toml::node* here = &root;
  std::string name;
  size_t i = 0;
  auto step_into_name = [&](bool last) -> bool {
    toml::table* t = here->as_table();
    if (!t) fail("'" + name + "' is inside something that is not a table");
    if (last) {
      t->insert_or_assign(name, *value_doc.get("value"));
      return true;
    }
    const bool indexed = i < key.size() && key[i] == '[';
    if (!t->get(name)) {
      if (indexed)
        t->insert(name, toml::array{});
      else
        t->insert(name, toml::table{});
    }
    here = t->get(name);
    return false;
  };
  while (i < key.size()) {
    if (key[i] == '"') {  // a quoted name, as TOML writes one holding a dot: materials."a.b".density
      const size_t close = key.find('"', i + 1);
      if (close == std::string::npos) fail("an unclosed \"");
      name = key.substr(i + 1, close - i - 1);
      i = close + 1;
      if (i < key.size() && key[i] != '.' && key[i] != '[')
        fail("a quoted name followed by '" + key.substr(i, 1) + "'");
    } else {
      const size_t end = key.find_first_of(".[", i);
      name = key.substr(i, end == std::string::npos ? std::string::npos : end - i);
      i = end == std::string::npos ? key.size() : end;
    }
    if (name.empty()) fail("an empty name in the path");
    if (step_into_name(i >= key.size())) return;
    while (i < key.size() && key[i] == '[') {
      const size_t close = key.find(']', i);
      if (close == std::string::npos) fail("an unclosed [");
      const std::string digits = key.substr(i + 1, close - i - 1);
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
        fail("[" + digits + "] is not an index");
      if (digits.size() > 9) fail("[" + digits + "] is past the end of any list");
      toml::array* a = here->as_array();
      const size_t index = std::stoul(digits);
      i = close + 1;
      // One past the end of an array of tables (or of an empty array) adds a table, when a key
      // inside it follows: shards[0].size = 0.01 where the file has no [[shards]].
      const bool tables =
          a && std::all_of(a->begin(), a->end(), [](const toml::node& n) { return n.is_table(); });
      if (a && index == a->size() && tables && i < key.size() && key[i] == '.') a->push_back(toml::table{});
      if (!a || index >= a->size()) fail("'" + name + "' has no element " + digits);
      if (i >= key.size()) {
        a->replace(a->begin() + long(index), *value_doc.get("value"));
        return;
      }
      here = a->get(index);
    }
    if (key[i] != '.') fail("expected '.' after ']'");
    ++i;
  }
  fail("an empty name in the path");
}

}  // namespace pd
