// Extension dispatch and the shared file reader of the mesh formats.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>

#include "host/geometry/mesh_io.h"
#include "host/io/input_file.h"

namespace pd {

namespace detail {

std::string read_file_bytes(const std::string& path) {
  std::string why;
  std::optional<std::string> read = read_input_file(path, why);
  if (!read) throw MeshError(path, "cannot read mesh file: " + why);
  std::string bytes = std::move(*read);
  if (bytes.empty()) throw MeshError(path, "the file is empty (allowed: a mesh with at least one triangle)");
  return bytes;
}

std::string printable(std::string_view text) {
  constexpr size_t kMax = 60;
  std::string out;
  for (size_t k = 0; k < text.size() && k < kMax; ++k) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += char(c);
    }
  }
  if (text.size() > kMax) out += "...";
  return out;
}

}  // namespace detail

TriMesh read_mesh(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == "obj") return read_obj(path);
  if (ext == "ply") return read_ply(path);
  if (ext == "stl") return read_stl(path);
  throw MeshError(path, "unknown mesh format '." + ext + "' (allowed: .obj, .ply, .stl)");
}

}  // namespace pd
