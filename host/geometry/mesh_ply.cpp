// Stanford PLY, ascii and binary little-endian: the `vertex` element's x, y, z and the `face`
// element's vertex_indices (or vertex_index) list; other elements and properties are skipped.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "host/geometry/mesh_io.h"
#include "host/io/atomic_file.h"

namespace pd {

namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

// A number read from the file, as it was written (an index of -1 read as -1.000000).
std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

struct Property {
  std::string name;
  Type type = Type::f32;
  bool list = false;
  Type count_type = Type::u8;  // for lists
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

const char* const kTypes = "char uchar short ushort int uint float double (or int8 ... float64)";

bool parse_type(const std::string& s, Type& t) {
  static const struct {
    const char* a;
    const char* b;
    Type t;
  } names[] = {{"char", "int8", Type::i8},      {"uchar", "uint8", Type::u8},
               {"short", "int16", Type::i16},   {"ushort", "uint16", Type::u16},
               {"int", "int32", Type::i32},     {"uint", "uint32", Type::u32},
               {"float", "float32", Type::f32}, {"double", "float64", Type::f64}};
  for (const auto& n : names)
    if (s == n.a || s == n.b) {
      t = n.t;
      return true;
    }
  return false;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 0;
}

// Sequential reader of the body, binary little-endian or ascii tokens.
class Body {
 public:
  Body(const std::string& path, const std::string& bytes, size_t start, bool binary)
      : path_(path), bytes_(bytes), pos_(start), binary_(binary) {}

  double value(Type t, const std::string& where) {
    return binary_ ? binary_value(t, where) : ascii_value(where);
  }

 private:
  double binary_value(Type t, const std::string& where) {
    const size_t n = type_size(t);
    if (pos_ + n > bytes_.size()) truncated(where);
    uint64_t u = 0;
    for (size_t k = 0; k < n; ++k) u |= uint64_t(uint8_t(bytes_[pos_ + k])) << (8 * k);
    pos_ += n;
    switch (t) {
      case Type::i8:
        return double(int8_t(u));
      case Type::u8:
        return double(uint8_t(u));
      case Type::i16:
        return double(int16_t(u));
      case Type::u16:
        return double(uint16_t(u));
      case Type::i32:
        return double(int32_t(u));
      case Type::u32:
        return double(uint32_t(u));
      case Type::f32: {
        const uint32_t w = uint32_t(u);
        float f;
        std::memcpy(&f, &w, 4);
        return f;
      }
      case Type::f64: {
        double d;
        std::memcpy(&d, &u, 8);
        return d;
      }
    }
    return 0;
  }

  double ascii_value(const std::string& where) {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    if (pos_ >= bytes_.size()) truncated(where);
    const size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    const std::string token = bytes_.substr(start, pos_ - start);
    char* stop = nullptr;
    const double v = std::strtod(token.c_str(), &stop);
    if (*stop != '\0')
      throw MeshError(path_,
                      where + ": '" + detail::printable(token) + "' is not a number (allowed: numbers)");
    return v;
  }

  [[noreturn]] void truncated(const std::string& where) const {
    throw MeshError(path_, where + ": the file ends early (allowed: as many values as the header declares)");
  }

  const std::string& path_;
  const std::string& bytes_;
  size_t pos_;
  bool binary_;
};

}  // namespace

TriMesh read_ply(const std::string& path) {
  return parse_ply(detail::read_file_bytes(path), path);
}

TriMesh parse_ply(const std::string& file_bytes, const std::string& path) {
  const std::string marked =
      without_utf8_mark(file_bytes).size() == file_bytes.size() ? "" : file_bytes.substr(3);
  const std::string& bytes = marked.empty() ? file_bytes : marked;  // (a copy only without a mark)
  auto fail = [&](const std::string& what, const std::string& allowed) {
    throw MeshError(path, what + " (allowed: " + allowed + ")");
  };

  // Header: magic, format, elements with their properties, end_header.
  const size_t header_end = bytes.find("end_header");
  if (bytes.compare(0, 3, "ply") != 0 || header_end == std::string::npos)
    fail("not a PLY file: no 'ply' ... 'end_header' header", "a PLY file");
  std::istringstream header(bytes.substr(0, header_end));
  std::string line, format;
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      words >> format;
    } else if (word == "element") {
      // The count is a whole number of at most 18 digits ("-1" would wrap around as a size_t).
      Element e;
      std::string count;
      words >> e.name >> count;
      if (!words || count.size() > 18 || count.find_first_not_of("0123456789") != std::string::npos)
        fail("bad element line '" + detail::printable(line) + "'",
             "element NAME COUNT, COUNT a whole number");
      e.count = std::stoull(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) fail("a property before any element", "element lines first");
      Property p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> p.name;
        p.list = true;
        if (!parse_type(count_type, p.count_type) || !parse_type(item_type, p.type))
          fail("unknown type in '" + detail::printable(line) + "'", kTypes);
      } else {
        words >> p.name;
        if (!parse_type(type, p.type)) fail("unknown type in '" + detail::printable(line) + "'", kTypes);
      }
      elements.back().properties.push_back(p);
    }
  }
  if (format != "ascii" && format != "binary_little_endian")
    fail("format '" + detail::printable(format) + "' is not supported", "ascii, binary_little_endian");
  size_t body_start = bytes.find('\n', header_end);
  body_start = body_start == std::string::npos ? bytes.size() : body_start + 1;

  // Body: elements in header order.
  TriMesh mesh;
  Body body(path, bytes, body_start, format != "ascii");
  bool has_faces = false;
  for (const Element& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    int indices = -1;
    for (size_t k = 0; k < e.properties.size(); ++k) {
      const std::string& n = e.properties[k].name;
      if (is_vertex && (n == "x" || n == "y" || n == "z")) xyz[n[0] - 'x'] = int(k);
      if (is_face && (n == "vertex_indices" || n == "vertex_index") && e.properties[k].list) indices = int(k);
    }
    if (is_vertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0))
      fail("the vertex element lacks x, y or z", "vertex properties x, y, z");
    if (is_face && indices < 0)
      fail("the face element lacks a vertex_indices list", "property list ... vertex_indices");
    has_faces = has_faces || is_face;

    // An element without properties has nothing in the body, however many items it declares.
    if (e.properties.empty()) continue;
    std::vector<int32_t> polygon;
    const std::string name = detail::printable(e.name);
    for (size_t i = 0; i < e.count; ++i) {
      const std::string where = name + " " + std::to_string(i);
      Vec3d v{};
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.list) {
          const double value = body.value(p.type, where);
          for (int c = 0; c < 3; ++c)
            if (int(k) == xyz[c]) v[c] = value;
          continue;
        }
        const double count = body.value(p.count_type, where);
        if (!(count >= 0) || count > 1e6) fail(where + ": bad list length", "0 to 1e6 items");
        polygon.clear();
        for (size_t q = 0; q < size_t(count); ++q) {
          const double index = body.value(p.type, where);
          if (int(k) != indices) continue;
          if (!(index >= 0) || index >= double(mesh.vertices.size()) || index != std::floor(index))
            fail(where + ": vertex index " + number_text(index) + " is out of range",
                 "0.." + std::to_string(long(mesh.vertices.size()) - 1));
          polygon.push_back(int32_t(index));
        }
        if (int(k) != indices) continue;
        if (polygon.size() < 3) fail(where + ": a face needs at least 3 vertices", "3 or more indices");
        detail::add_polygon(mesh, polygon);
      }
      if (is_vertex) mesh.vertices.push_back(v);
    }
  }
  if (!has_faces || mesh.triangles.empty()) {
    const bool strips =
        std::any_of(elements.begin(), elements.end(), [](const Element& e) { return e.name == "tristrips"; });
    fail(strips ? "no faces, only triangle strips (a tristrips element), which are not read" : "no faces",
         "a mesh with at least one triangle in a face element");
  }
  return mesh;
}

// Binary output copies doubles and ints as they are in memory.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "binary PLY/STL writers assume a little-endian host");

void write_ply(const TriMesh& mesh, const std::string& path, bool binary) {
  write_file_atomic(path, [&](std::ostream& out) {
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
        << "comment perifrac mesh\nelement vertex " << mesh.vertices.size()
        << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << mesh.triangles.size()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    char buf[128];
    for (const Vec3d& v : mesh.vertices) {
      if (binary) {
        out.write(reinterpret_cast<const char*>(v.data()), 3 * sizeof(double));
      } else {
        std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", v[0], v[1], v[2]);
        out << buf;
      }
    }
    for (const Triangle& t : mesh.triangles) {
      if (binary) {
        out.put(char(3));
        out.write(reinterpret_cast<const char*>(t.data()), 3 * sizeof(int32_t));
      } else {
        out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
      }
    }
  });
}

}  // namespace pd
