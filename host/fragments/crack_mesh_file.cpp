#include "host/fragments/crack_mesh_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "host/fragments/obj_text.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/tri_mesh.h"
#include "host/io/atomic_file.h"

namespace pd {

size_t CrackSurface::crack_count() const {
  return size_t(std::count(crack.begin(), crack.end(), uint8_t(1)));
}

std::string crack_mesh_file_name(int64_t frame, std::string_view extension) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%05lld", static_cast<long long>(frame));
  return "crack_mesh_" + std::string(digits) + "." + std::string(extension);
}

void write_crack_obj(const std::string& path, const CrackSurface& s, const std::string& comment) {
  std::vector<std::string> text{"# perifrac crack mesh: " + comment +
                                "\n# the original surface (g surface) and the crack surfaces (g crack), "
                                "docs/fragments.md\n"};
  append_lines(text, s.vertices.size(), [&](std::string& out, size_t v) {
    out += 'v';
    for (double x : s.vertices[v]) append_coordinate(out, x);
    out += '\n';
  });
  // The original surface, then the cracks, each under its group and material name.
  std::vector<size_t> faces;
  for (uint8_t crack = 0; crack < 2; ++crack) {
    text.emplace_back(crack ? "g crack\nusemtl crack\n" : "g surface\nusemtl surface\n");
    faces.clear();
    for (size_t f = 0; f < s.triangles.size(); ++f)
      if (s.crack[f] == crack) faces.push_back(f);
    append_lines(text, faces.size(), [&](std::string& out, size_t k) {
      out += 'f';
      for (int32_t v : s.triangles[faces[k]]) append_index(out, v + 1);
      out += '\n';
    });
  }
  write_parts_atomic(path, text);
}

// Binary output copies floats and ints as they are in memory.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the binary PLY writer assumes a little-endian host");

// A face record: 3, three vertex indices, the crack flag and the owning particle; files written
// before the particle property have records of kPlyOldFaceBytes.
constexpr size_t kPlyFaceBytes = 18, kPlyOldFaceBytes = 14;

void write_crack_ply(const std::string& path, const CrackSurface& s, const std::string& comment) {
  if (!s.particle.empty() && s.particle.size() != s.triangles.size())
    throw std::invalid_argument("write_crack_ply: " + std::to_string(s.particle.size()) + " owners for " +
                                std::to_string(s.triangles.size()) + " triangles");
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment perifrac crack mesh: " << comment
         << "\nelement vertex " << s.vertices.size()
         << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << s.triangles.size()
         << "\nproperty list uchar int vertex_indices\nproperty uchar crack\nproperty int "
            "particle\nend_header\n";
  std::string bytes = header.str();
  const size_t start = bytes.size();
  bytes.resize(start + 12 * s.vertices.size() + kPlyFaceBytes * s.triangles.size());
  char* p = &bytes[start];
  for (const Vec3d& v : s.vertices) {
    const float x[3] = {float(v[0]), float(v[1]), float(v[2])};
    std::memcpy(p, x, 12);
    p += 12;
  }
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    *p++ = char(3);
    std::memcpy(p, s.triangles[f].data(), 12);
    p += 12;
    *p++ = char(s.crack[f]);
    const int32_t owner = s.particle.empty() ? -1 : s.particle[f];
    std::memcpy(p, &owner, 4);
    p += 4;
  }
  write_file_atomic(path, bytes);
}

namespace {

CrackSurface read_crack_obj(const std::string& path, const std::string& text) {
  CrackSurface s;
  std::istringstream in(text);
  std::string line, word;
  uint8_t crack = 0;
  size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream l(line);
    auto fail = [&](const std::string& what) {
      throw MeshError(path, "line " + std::to_string(line_no) + ": " + what +
                                " (allowed: the crack mesh OBJ layout of docs/fragments.md)");
    };
    if (!(l >> word) || word[0] == '#') continue;
    if (word == "v") {
      Vec3d v;
      if (!(l >> v[0] >> v[1] >> v[2])) fail("a vertex needs 3 coordinates");
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
        fail("a vertex is not finite");
      s.vertices.push_back(v);
    } else if (word == "g" || word == "usemtl") {
      if (!(l >> word) || (word != "surface" && word != "crack")) fail("unknown group");
      crack = word == "crack";
    } else if (word == "f") {
      std::array<int32_t, 3> t;
      for (int32_t& i : t) {
        if (!(l >> i) || i < 1 || size_t(i) > s.vertices.size()) fail("bad vertex index");
        --i;
      }
      s.triangles.push_back(t);
      s.crack.push_back(crack);
    } else {
      fail("unexpected '" + detail::printable(word) + "'");
    }
  }
  return s;
}

CrackSurface read_crack_ply(const std::string& path, const std::string& bytes) {
  auto fail = [&](const std::string& what) {
    throw MeshError(path, what + " (allowed: the crack mesh PLY layout of docs/fragments.md)");
  };
  const size_t end = bytes.find("end_header\n");
  if (end == std::string::npos) fail("no end_header");
  std::istringstream header(bytes.substr(0, end));
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(header, line))
    if (line.rfind("comment", 0) != 0) lines.push_back(line);
  size_t nv = 0, nf = 0;
  // The layout: 9 lines, and a 10th with the owning particle (files written since it exists).
  const bool owners = lines.size() == 10 && lines[9] == "property int particle";
  if ((lines.size() != 9 && !owners) || lines[0] != "ply" || lines[1] != "format binary_little_endian 1.0" ||
      std::sscanf(lines[2].c_str(), "element vertex %zu", &nv) != 1 || lines[3] != "property float x" ||
      lines[4] != "property float y" || lines[5] != "property float z" ||
      std::sscanf(lines[6].c_str(), "element face %zu", &nf) != 1 ||
      lines[7] != "property list uchar int vertex_indices" || lines[8] != "property uchar crack")
    fail("unexpected header");
  const size_t start = end + std::strlen("end_header\n");
  const size_t face_bytes = owners ? kPlyFaceBytes : kPlyOldFaceBytes;
  // Counts the file cannot hold are refused before they are multiplied (no wrap-around).
  const size_t body = bytes.size() - start;
  if (nv > body / 12 || nf > body / face_bytes || bytes.size() != start + 12 * nv + face_bytes * nf)
    fail("the body is not " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces long");
  CrackSurface s;
  const char* p = bytes.data() + start;
  for (size_t v = 0; v < nv; ++v, p += 12) {
    float x[3];
    std::memcpy(x, p, 12);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      fail("vertex " + std::to_string(v) + " is not finite");
    s.vertices.push_back({x[0], x[1], x[2]});
  }
  for (size_t f = 0; f < nf; ++f, p += face_bytes) {
    std::array<int32_t, 3> t;
    std::memcpy(t.data(), p + 1, 12);
    if (p[0] != 3) fail("face " + std::to_string(f) + " is not a triangle");
    for (int32_t i : t)
      if (i < 0 || size_t(i) >= nv) fail("face " + std::to_string(f) + " has vertex " + std::to_string(i));
    s.triangles.push_back(t);
    s.crack.push_back(uint8_t(p[13]));
    if (!owners) continue;
    int32_t owner;
    std::memcpy(&owner, p + 14, 4);
    s.particle.push_back(owner);
  }
  return s;
}

}  // namespace

CrackSurface read_crack_mesh(const std::string& path) {
  const std::string bytes = detail::read_file_bytes(path);
  const std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  if (ext == ".obj") return read_crack_obj(path, bytes);
  if (ext == ".ply") return read_crack_ply(path, bytes);
  throw MeshError(path, "unknown extension (allowed: .obj, .ply)");
}

}  // namespace pd
