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

void add_polygon(TriMesh& mesh, const std::vector<int32_t>& polygon) {
  const size_t n = polygon.size();
  auto corner = [&](size_t k) { return polygon[k % n]; };
  size_t apex = 0;
  if (n > 3) {
    double size2 = 0;  // the polygon's size, squared: the scale of "no area"
    for (size_t k = 1; k < n; ++k)
      size2 = std::max(size2, distance2(mesh.vertices[corner(k)], mesh.vertices[corner(0)]));
    auto has_area = [&](size_t a, size_t b, size_t c) {
      const Vec3d &p = mesh.vertices[corner(a)], &q = mesh.vertices[corner(b)], &r = mesh.vertices[corner(c)];
      const Vec3d n = cross(q - p, r - p);
      return dot(n, n) > 1e-24 * size2 * size2;
    };
    for (size_t r = 0; r < n; ++r) {
      bool all = true;
      for (size_t k = 1; all && k + 1 < n; ++k) all = has_area(r, r + k, r + k + 1);
      if (all) {
        apex = r;
        break;
      }
    }
  }
  for (size_t k = 1; k + 1 < n; ++k)
    mesh.triangles.push_back({corner(apex), corner(apex + k), corner(apex + k + 1)});
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
