// Extension dispatch and the shared file reader of the mesh formats.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
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

std::string_view without_utf8_mark(const std::string& bytes) {
  std::string_view view(bytes);
  if (view.substr(0, 3) == "\xEF\xBB\xBF") view.remove_prefix(3);
  return view;
}

namespace {

// Vertices no triangle uses left out (a stray point would still set the bounds that place the
// body); a triangle naming a vertex that is not there keeps the mesh as it is, for its check.
void drop_unused_vertices(TriMesh& mesh) {
  std::vector<int32_t> remap(mesh.vertices.size(), -1);
  for (const Triangle& t : mesh.triangles)
    for (int32_t c : t) {
      if (c < 0 || size_t(c) >= mesh.vertices.size()) return;
      remap[size_t(c)] = 0;
    }
  std::vector<Vec3d> kept;
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    if (remap[v] == 0) {
      remap[v] = int32_t(kept.size());
      kept.push_back(mesh.vertices[v]);
    }
  if (kept.size() == mesh.vertices.size()) return;
  mesh.vertices = std::move(kept);
  for (Triangle& t : mesh.triangles)
    for (int32_t& c : t) c = remap[size_t(c)];
}

TriMesh read_by_extension(const std::string& path, const std::string& ext) {
  if (ext == ".obj") return read_obj(path);
  if (ext == ".ply") return read_ply(path);
  return read_stl(path);
}

}  // namespace

TriMesh read_mesh(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw MeshError(path, "is a folder, not a mesh file (allowed: an .obj, .ply or .stl file)");
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".obj" || ext == ".ply" || ext == ".stl") {
    TriMesh mesh = read_by_extension(path, ext);
    drop_unused_vertices(mesh);
    return mesh;
  }
  throw MeshError(path,
                  (ext.empty() ? std::string("has no file extension") : "unknown mesh format '" + ext + "'") +
                      " (allowed: .obj, .ply, .stl)");
}

}  // namespace pd
