// Wavefront OBJ: `v x y z [w]` vertices and `f` polygons (indices 1-based, negative = relative
// to the end, with optional /texture/normal parts); every other statement is ignored.
#include <cstdlib>
#include <string>

#include "host/geometry/mesh_io.h"
#include "host/io/atomic_file.h"

namespace pd {

namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

// Tokenizer over one line.
struct Line {
  const char* p;
  const char* end;
  bool next(std::string& token) {
    while (p < end && is_space(*p)) ++p;
    const char* start = p;
    while (p < end && !is_space(*p)) ++p;
    token.assign(start, p);
    return !token.empty();
  }
};

}  // namespace

TriMesh read_obj(const std::string& path) {
  return parse_obj(detail::read_file_bytes(path), path);
}

TriMesh parse_obj(const std::string& bytes, const std::string& path) {
  const std::string_view text = without_utf8_mark(bytes);
  TriMesh mesh;
  std::string token;
  std::vector<int32_t> polygon;
  size_t line_no = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t eol = text.find_first_of("\r\n", pos);  // lines end in LF, CR LF or CR alone
    if (eol == std::string::npos) eol = text.size();
    ++line_no;
    Line line{text.data() + pos, text.data() + eol};
    pos = eol + (text.compare(eol, 2, "\r\n") == 0 ? 2 : 1);
    auto fail = [&](const std::string& what, const std::string& allowed) {
      throw MeshError(path, "line " + std::to_string(line_no) + ": " + what + " (allowed: " + allowed + ")");
    };
    if (!line.next(token) || token[0] == '#') continue;

    if (token == "v") {
      // Vertex: three numbers (an optional fourth, w, is ignored). nan/inf parse and are
      // reported by the mesh check with the vertex number.
      Vec3d v{};
      for (int c = 0; c < 3; ++c) {
        if (!line.next(token)) fail("a vertex needs 3 coordinates", "v x y z");
        char* stop = nullptr;
        v[c] = std::strtod(token.c_str(), &stop);
        if (*stop != '\0') fail("'" + detail::printable(token) + "' is not a number", "v x y z");
      }
      mesh.vertices.push_back(v);
    } else if (token == "f") {
      // Face: the vertex index before the first '/', 1-based or negative (relative).
      polygon.clear();
      while (line.next(token) && token[0] != '#') {  // a comment may end the line
        char* stop = nullptr;
        const long index = std::strtol(token.c_str(), &stop, 10);
        if (stop == token.c_str() || (*stop != '\0' && *stop != '/'))
          fail("'" + detail::printable(token) + "' is not a vertex index", "f i j k ... with i, j[/vt][/vn]");
        const long n = long(mesh.vertices.size());
        const long resolved = index > 0 ? index - 1 : n + index;
        if (index == 0 || resolved < 0 || resolved >= n)
          fail("vertex index " + std::to_string(index) + " does not name one of the " + std::to_string(n) +
                   " vertices so far",
               "1.." + std::to_string(n) + " or -1..-" + std::to_string(n));
        polygon.push_back(int32_t(resolved));
      }
      if (polygon.size() < 3) fail("a face needs at least 3 vertices", "f i j k ...");
      detail::add_polygon(mesh, polygon);
    }
  }
  if (mesh.triangles.empty()) throw MeshError(path, "no faces (allowed: a mesh with at least one triangle)");
  return mesh;
}

void write_obj(const TriMesh& mesh, const std::string& path) {
  write_file_atomic(path, [&](std::ostream& out) {
    char buf[128];
    out << "# perifrac mesh: " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
        << " triangles\n";
    for (const Vec3d& v : mesh.vertices) {
      std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", v[0], v[1], v[2]);
      out << buf;
    }
    for (const Triangle& t : mesh.triangles)
      out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  });
}

}  // namespace pd
