// Helpers of the optional tests that run outside tools (Blender, ParaView) on our files: find a
// program on PATH, run a command, and take a script out of the documentation.
#pragma once

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pd::testing {

// The program's path if it is on PATH, else empty.
inline std::string find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / name;
    if (!dir.empty() && std::filesystem::exists(candidate)) return candidate.string();
  }
  return "";
}

// Runs `command`, returning its standard output and error.
inline std::string run_command(const std::string& command) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf;
  size_t got;
  while ((got = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), got);
  pclose(pipe);
  return out;
}

// The ```python block after the line <!-- `marker` --> of the document `doc` (relative to the
// source tree, e.g. "docs/fragments.md"); empty when there is none.
inline std::string doc_script(const std::string& doc, const std::string& marker) {
  std::ifstream in(std::string(PERIFRAC_SOURCE_DIR) + "/" + doc);
  std::string line, script;
  bool marked = false, inside = false;
  while (std::getline(in, line)) {
    if (inside && line == "```") break;
    if (inside) script += line + "\n";
    if (marked && line == "```python") inside = true;
    if (line == "<!-- " + marker + " -->") marked = true;
  }
  return script;
}

}  // namespace pd::testing
