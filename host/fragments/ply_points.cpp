#include "host/fragments/ply_points.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <ostream>
#include <sstream>
#include <vector>

#include "host/io/atomic_file.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "PLY files are written little endian");

namespace pd {

namespace {

std::array<float, 3> float3(Vec3 v) {
  return {float(v.x), float(v.y), float(v.z)};
}

// Copies `value`'s bytes to `at`; returns the end.
template <class T>
char* pack(char* at, const T& value) {
  std::memcpy(at, &value, sizeof value);
  return at + sizeof value;
}

// PLY scalar types: name, bytes, and how to read one as double.
struct PlyType {
  const char* name;
  size_t bytes;
  double (*read)(const char*);
};

template <class T>
double read_as_double(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return double(v);
}

constexpr PlyType kPlyTypes[] = {
    {"char", 1, read_as_double<int8_t>},     {"int8", 1, read_as_double<int8_t>},
    {"uchar", 1, read_as_double<uint8_t>},   {"uint8", 1, read_as_double<uint8_t>},
    {"short", 2, read_as_double<int16_t>},   {"int16", 2, read_as_double<int16_t>},
    {"ushort", 2, read_as_double<uint16_t>}, {"uint16", 2, read_as_double<uint16_t>},
    {"int", 4, read_as_double<int32_t>},     {"int32", 4, read_as_double<int32_t>},
    {"uint", 4, read_as_double<uint32_t>},   {"uint32", 4, read_as_double<uint32_t>},
    {"float", 4, read_as_double<float>},     {"float32", 4, read_as_double<float>},
    {"double", 8, read_as_double<double>},   {"float64", 8, read_as_double<double>},
};

struct Property {
  std::string name;
  const PlyType* type;
  size_t offset;  // within a vertex record
};

}  // namespace

std::string points_file_name(int64_t frame) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%05lld", static_cast<long long>(frame));
  return "points_" + std::string(digits) + ".ply";
}

void write_ply_points(const std::string& path, const FrameData& f) {
  check_sizes(f);
  const bool component = !f.component.empty();
  write_file_atomic(path, [&](std::ostream& out) {
    // Text header.
    char comment[160];
    std::snprintf(comment, sizeof comment, "comment perifrac frame %" PRId64 " step %" PRId64 " time %.17g\n",
                  f.frame, f.step, f.time);
    out << "ply\nformat binary_little_endian 1.0\n" << comment << "element vertex " << f.size() << "\n";
    for (const char* name : {"x", "y", "z", "vx", "vy", "vz", "damage"})
      out << "property float " << name << "\n";
    out << "property int body\n";
    if (component) out << "property int component\n";
    out << "end_header\n";
    // Records, packed into a buffer a block of particles at a time.
    const size_t record = component ? 36 : 32, block = 1 << 14;
    std::vector<char> buffer(record * block);
    for (size_t first = 0; first < f.size(); first += block) {
      const size_t last = std::min(f.size(), first + block);
      char* at = buffer.data();
      for (size_t i = first; i < last; ++i) {
        at = pack(at, float3(f.position[i]));
        at = pack(at, float3(f.velocity[i]));
        at = pack(at, f.damage[i]);
        at = pack(at, f.body[i]);
        if (component) at = pack(at, f.component[i]);
      }
      out.write(buffer.data(), at - buffer.data());
    }
  });
}

FrameData read_ply_points(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error_errno("read", path, errno);
  auto fail = [&](const std::string& why) { return io_error("read", path, why); };

  // Header: format, the vertex element and its scalar properties, our comment line.
  FrameData f;
  std::string line;
  if (!std::getline(in, line) || line != "ply") throw fail("not a PLY file (no 'ply' line)");
  uint64_t vertices = 0;
  bool format = false, in_vertex = false, seen_vertex = false;
  std::vector<Property> props;
  size_t record = 0;
  while (true) {
    if (!std::getline(in, line)) throw fail("truncated: no end_header");
    if (line == "end_header") break;
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string kind;
      words >> kind;
      if (kind != "binary_little_endian") throw fail("format '" + kind + "', expected binary_little_endian");
      format = true;
    } else if (word == "comment") {
      long long frame = 0, step = 0;
      double time = 0;
      if (std::sscanf(line.c_str(), "comment perifrac frame %lld step %lld time %lf", &frame, &step, &time) ==
          3)
        f.frame = frame, f.step = step, f.time = time;
    } else if (word == "element") {
      std::string name;
      words >> name;
      in_vertex = !seen_vertex && name == "vertex";
      if (!seen_vertex && !in_vertex) throw fail("first element is '" + name + "', expected vertex");
      if (in_vertex && !(words >> vertices)) throw fail("vertex element without a count");
      seen_vertex = true;
    } else if (word == "property" && in_vertex) {
      std::string type, name;
      words >> type >> name;
      const PlyType* t = nullptr;
      for (const PlyType& candidate : kPlyTypes)
        if (type == candidate.name) t = &candidate;
      if (t == nullptr) throw fail("vertex property '" + type + " " + name + "' is not a scalar property");
      props.push_back({name, t, record});
      record += t->bytes;
    }
  }
  if (!format) throw fail("no format line");
  if (!seen_vertex) throw fail("no vertex element");
  auto find = [&](const char* name) -> const Property* {
    for (const Property& p : props)
      if (p.name == name) return &p;
    return nullptr;
  };
  const Property *x = find("x"), *y = find("y"), *z = find("z");
  if (!x || !y || !z) throw fail("vertex has no x, y and z properties");

  // Vertex records, checked against the bytes left before allocating.
  const auto body_start = in.tellg();
  in.seekg(0, std::ios::end);
  const uint64_t left = uint64_t(in.tellg() - body_start);
  if (record == 0 || vertices > left / record)
    throw fail("truncated: " + std::to_string(vertices) + " vertices need more than the " +
               std::to_string(left) + " bytes left");
  in.seekg(body_start);
  std::vector<char> bytes(size_t(vertices) * record);
  in.read(bytes.data(), std::streamsize(bytes.size()));
  if (!in) throw fail("truncated vertex data");

  // Per-particle arrays; absent properties read as 0.
  auto value = [&](const Property* p, size_t i) {
    return p ? p->type->read(&bytes[i * record + p->offset]) : 0.0;
  };
  const Property *vx = find("vx"), *vy = find("vy"), *vz = find("vz"), *damage = find("damage"),
                 *body = find("body"), *component = find("component");
  const size_t n = size_t(vertices);
  f.position.resize(n);
  f.velocity.resize(n);
  f.damage.resize(n);
  f.body.resize(n);
  if (component) f.component.resize(n);
  for (size_t i = 0; i < n; ++i) {
    f.position[i] = {real(value(x, i)), real(value(y, i)), real(value(z, i))};
    f.velocity[i] = {real(value(vx, i)), real(value(vy, i)), real(value(vz, i))};
    f.damage[i] = float(value(damage, i));
    f.body[i] = int32_t(value(body, i));
    if (component) f.component[i] = int32_t(value(component, i));
  }
  return f;
}

}  // namespace pd
