// Scans every file of a run's output folder for a number that is not finite: frame and rest files
// through their readers, fragment files field by field, binary PLY vertices property by property,
// and text files (CSV, OBJ, VTU, PVD, the manifest) token by token. Images, movies and the
// checkpoint are skipped. Returns "file: what" for each problem (empty: all finite).
#pragma once

#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/fragments/fragments_file.h"
#include "host/io/frame_file.h"
#include "tests/support/temp_dir.h"

namespace pd::testing {

// "nan" or "inf" as a token of its own (not inside a word such as "info").
inline bool has_non_finite_token(const std::string& text) {
  std::string lower(text.size(), ' ');
  for (size_t i = 0; i < text.size(); ++i) lower[i] = char(std::tolower(static_cast<unsigned char>(text[i])));
  for (const char* token : {"nan", "inf"})
    for (size_t at = lower.find(token); at != std::string::npos; at = lower.find(token, at + 1)) {
      const bool start = at == 0 || !std::isalpha(static_cast<unsigned char>(lower[at - 1]));
      const bool end = at + 3 >= lower.size() || !std::isalpha(static_cast<unsigned char>(lower[at + 3])) ||
                       lower.compare(at, 8, "infinity") == 0;
      if (start && end) return true;
    }
  return false;
}

// The float properties of a binary little-endian PLY's vertices (properties of 4 bytes each).
inline bool ply_vertices_finite(const std::string& bytes) {
  const size_t header_end = bytes.find("end_header\n");
  if (header_end == std::string::npos || bytes.find("binary_little_endian") == std::string::npos)
    return !has_non_finite_token(bytes);
  std::istringstream header(bytes.substr(0, header_end));
  size_t vertices = 0;
  std::vector<bool> is_float;
  bool in_vertex = false;
  for (std::string line; std::getline(header, line);) {
    std::istringstream words(line);
    std::string word, type;
    words >> word;
    if (word == "element") {
      words >> type;
      in_vertex = type == "vertex";
      if (in_vertex) words >> vertices;
    } else if (word == "property" && in_vertex) {
      words >> type;
      is_float.push_back(type == "float");
    }
  }
  const char* data = bytes.data() + header_end + std::strlen("end_header\n");
  const size_t stride = 4 * is_float.size();
  if (bytes.size() < header_end + 11 + vertices * stride) return false;
  for (size_t v = 0; v < vertices; ++v)
    for (size_t p = 0; p < is_float.size(); ++p) {
      float x;
      std::memcpy(&x, data + v * stride + 4 * p, 4);
      if (is_float[p] && !std::isfinite(x)) return false;
    }
  return true;
}

inline bool all_finite(const std::vector<Vec3>& v) {
  for (const Vec3& x : v)
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return false;
  return true;
}

inline std::vector<std::string> non_finite_outputs(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> problems;
  if (!fs::exists(dir)) return problems;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string path = entry.path().string(), ext = entry.path().extension().string();
    const std::string name = entry.path().filename().string();
    if (ext == ".pfr" && name == "rest.pfr") {
      if (!all_finite(read_rest_file(path).position)) problems.push_back(path + ": rest position");
    } else if (ext == ".pfr") {
      const FrameData f = read_frame_file(path);
      if (!all_finite(f.position) || !all_finite(f.velocity) || !std::isfinite(f.time))
        problems.push_back(path + ": position, velocity or time");
      for (float d : f.damage)
        if (!std::isfinite(d)) {
          problems.push_back(path + ": damage");
          break;
        }
    } else if (ext == ".pfg") {
      for (const Fragment& g : read_fragments_file(path).fragments)
        if (!g.rotation.allFinite() || !g.translation.allFinite() || !std::isfinite(g.blend)) {
          problems.push_back(path + ": fragment " + std::to_string(g.id) + " transform");
          break;
        }
    } else if (ext == ".ply") {
      if (!ply_vertices_finite(read_all(path))) problems.push_back(path + ": a vertex");
    } else if (ext == ".csv" || ext == ".obj" || ext == ".vtu" || ext == ".pvd" || ext == ".manifest" ||
               ext == ".mtl") {
      if (has_non_finite_token(read_all(path))) problems.push_back(path + ": nan or inf in the text");
    }
  }
  return problems;
}

}  // namespace pd::testing
