// STL, binary (80-byte header, count, 50-byte facets) or ascii (solid/facet/vertex). Facets
// carry their own corners; bit-identical corners are merged so the mesh is indexed.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include "host/geometry/mesh_io.h"
#include "host/io/atomic_file.h"

namespace pd {

namespace {

// Merges corners with identical coordinates into one vertex.
class Welder {
 public:
  explicit Welder(TriMesh& mesh) : mesh_(mesh) {}
  int32_t add(const Vec3d& v) {
    // NaN is unordered, so the map would take a corner with one for an unrelated vertex and the
    // NaN would vanish: a non-finite corner stays a vertex of its own, for the mesh check to report.
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      mesh_.vertices.push_back(v);
      return int32_t(mesh_.vertices.size() - 1);
    }
    const auto [it, inserted] = index_.emplace(v, int32_t(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(v);
    return it->second;
  }

 private:
  TriMesh& mesh_;
  std::map<Vec3d, int32_t> index_;
};

float le_float(const char* p) {
  uint32_t u = 0;
  for (int k = 0; k < 4; ++k) u |= uint32_t(uint8_t(p[k])) << (8 * k);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

TriMesh read_binary(const std::string& path, const std::string& bytes, uint32_t count) {
  TriMesh mesh;
  Welder welder(mesh);
  for (uint32_t f = 0; f < count; ++f) {
    const char* facet = bytes.data() + 84 + size_t(f) * 50 + 12;  // skip the normal
    Triangle t{};
    for (int c = 0; c < 3; ++c)
      t[c] =
          welder.add({le_float(facet + 12 * c), le_float(facet + 12 * c + 4), le_float(facet + 12 * c + 8)});
    mesh.triangles.push_back(t);
  }
  if (mesh.triangles.empty()) throw MeshError(path, "no facets (allowed: a mesh with at least one triangle)");
  return mesh;
}

// Keywords are compared in lower case (some exporters write SOLID, FACET, VERTEX).
std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

TriMesh read_ascii(const std::string& path, const std::string& text) {
  TriMesh mesh;
  Welder welder(mesh);
  Triangle t{};
  int corner = 0, facet_vertices = 0;
  bool ended = false;  // an endsolid line seen
  size_t line_no = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    const std::string line = lower(text.substr(pos, eol - pos));
    pos = eol + 1;
    ++line_no;
    const size_t start = line.find_first_not_of(" \t\r");
    if (start != std::string::npos && line.compare(start, 8, "endsolid") == 0) ended = true;
    if (start == std::string::npos || line.compare(start, 6, "vertex") != 0) {
      if (start != std::string::npos && line.compare(start, 8, "endfacet") == 0) {
        if (facet_vertices != 3)
          throw MeshError(path, "line " + std::to_string(line_no) + ": a facet of " +
                                    std::to_string(facet_vertices) +
                                    " vertices (allowed: 3 vertices per facet)");
        facet_vertices = 0;
      }
      continue;
    }
    ++facet_vertices;
    // "vertex x y z"
    Vec3d v{};
    const char* p = line.c_str() + start + 6;
    for (int c = 0; c < 3; ++c) {
      char* stop = nullptr;
      v[c] = std::strtod(p, &stop);
      if (stop == p)
        throw MeshError(
            path, "line " + std::to_string(line_no) + ": a vertex needs 3 numbers (allowed: vertex x y z)");
      p = stop;
    }
    t[corner++] = welder.add(v);
    if (corner == 3) {
      mesh.triangles.push_back(t);
      corner = 0;
    }
  }
  if (mesh.triangles.empty()) throw MeshError(path, "no facets (allowed: a mesh with at least one triangle)");
  if (!ended || facet_vertices != 0)
    throw MeshError(path,
                    "the file ends before its 'endsolid' line: cut short? (allowed: a whole ascii STL, "
                    "solid ... endsolid)");
  return mesh;
}

}  // namespace

TriMesh read_stl(const std::string& path) {
  return parse_stl(detail::read_file_bytes(path), path);
}

TriMesh parse_stl(const std::string& bytes, const std::string& path) {
  // Binary when the size matches the facet count of the header; ascii files start with "solid"
  // (binary headers may too, so the size decides first).
  if (bytes.size() >= 84) {
    uint32_t count = 0;
    for (int k = 0; k < 4; ++k) count |= uint32_t(uint8_t(bytes[80 + k])) << (8 * k);
    if (bytes.size() == 84 + size_t(count) * 50) return read_binary(path, bytes, count);
  }
  const std::string marked = without_utf8_mark(bytes).size() == bytes.size() ? "" : bytes.substr(3);
  const std::string& text = marked.empty() ? bytes : marked;  // (a copy only without a mark)
  if (lower(text.substr(0, 5)) == "solid") return read_ascii(path, text);
  throw MeshError(path,
                  "neither binary STL (size 84 + 50 x facet count) nor ascii STL (starts with 'solid') "
                  "(allowed: binary or ascii STL)");
}

void write_stl(const TriMesh& mesh, const std::string& path, bool binary) {
  write_file_atomic(path, [&](std::ostream& out) {
    auto normal = [&](const Triangle& t) {
      const Vec3d n =
          cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
      const double len = norm(n);
      return len > 0 ? (1 / len) * n : Vec3d{0, 0, 0};
    };
    if (!binary) {
      char buf[160];
      out << "solid perifrac\n";
      for (const Triangle& t : mesh.triangles) {
        const Vec3d n = normal(t);
        std::snprintf(buf, sizeof buf, "  facet normal %.9g %.9g %.9g\n    outer loop\n", n[0], n[1], n[2]);
        out << buf;
        for (int c = 0; c < 3; ++c) {
          const Vec3d& v = mesh.vertices[t[c]];
          std::snprintf(buf, sizeof buf, "      vertex %.17g %.17g %.17g\n", v[0], v[1], v[2]);
          out << buf;
        }
        out << "    endloop\n  endfacet\n";
      }
      out << "endsolid perifrac\n";
      return;
    }
    // Binary: float32 little-endian (the host's order, see mesh_ply.cpp).
    char header[80] = "perifrac binary STL";
    out.write(header, 80);
    const uint32_t count = uint32_t(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (const Triangle& t : mesh.triangles) {
      float facet[12];
      const Vec3d n = normal(t);
      for (int c = 0; c < 3; ++c) facet[c] = float(n[c]);
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) facet[3 + 3 * k + c] = float(mesh.vertices[t[k]][c]);
      out.write(reinterpret_cast<const char*>(facet), sizeof facet);
      const uint16_t attribute = 0;
      out.write(reinterpret_cast<const char*>(&attribute), 2);
    }
  });
}

}  // namespace pd
