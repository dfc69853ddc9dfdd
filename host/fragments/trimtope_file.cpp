#include "host/fragments/trimtope_file.h"

#include <cmath>
#include <cstring>

#include "host/io/atomic_file.h"
#include "host/io/byte_file.h"

namespace pd {

namespace {

constexpr size_t kHeaderBytes = 40;

void put3(std::string& out, const Vec3d& v) {
  for (double x : v) put_bytes(out, float(x));
}

// float32 of x rounded away from the box's inside (lo down, hi up).
float outward(double x, bool up) {
  float f = float(x);
  if (up && double(f) < x) f = std::nextafter(f, INFINITY);
  if (!up && double(f) > x) f = std::nextafter(f, -INFINITY);
  return f;
}

// Three float32 values, widened.
// Three floats, finite (a number that is not is damage).
Vec3d get3(ByteReader& r) {
  const float x = r.get<float>(), y = r.get<float>(), z = r.get<float>();
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) r.fail("a point or normal is not finite");
  return {x, y, z};
}

// Reads a CSR offset array of n + 1 entries that must start at 0, never decrease and end at
// `total`.
std::vector<int64_t> read_offsets(ByteReader& r, uint64_t n, uint64_t total, const char* what) {
  std::vector<int64_t> o(size_t(n + 1));
  for (auto& v : o) v = r.get<int64_t>();
  if (o[0] != 0 || uint64_t(o.back()) != total)
    r.fail(std::string(what) + " offsets do not match the counts");
  for (size_t k = 1; k < o.size(); ++k)
    if (o[k] < o[k - 1]) r.fail(std::string(what) + " offsets decrease");
  return o;
}

}  // namespace

void write_trimtopes_file(const std::string& path, const RestTrimtopes& t) {
  const uint64_t n = t.size(), planes = t.plane_normal.size(), tris = t.tri_vertex.size() / 3;
  std::string out;
  out.reserve(kHeaderBytes + n * 64 + planes * 16 + tris * 36);
  out.append(kTrimtopesMagic, 8);
  put_bytes(out, kTrimtopesVersion);
  put_bytes(out, uint32_t(0));
  put_bytes(out, n);
  put_bytes(out, planes);
  put_bytes(out, tris);
  for (int32_t p : t.particle) put_bytes(out, p);
  for (const Vec3d& s : t.site) put3(out, s);
  for (int64_t o : t.plane_start) put_bytes(out, o);
  for (const Vec3d& m : t.plane_normal) put3(out, m);
  for (double d : t.plane_offset) put_bytes(out, float(d));
  for (int64_t o : t.tri_start) put_bytes(out, o);
  for (const Vec3d& v : t.tri_vertex) put3(out, v);
  for (const Box3d& b : t.box) {
    for (double x : b.lo) put_bytes(out, outward(x, false));
    for (double x : b.hi) put_bytes(out, outward(x, true));
  }
  write_file_atomic(path, out);
}

RestTrimtopes read_trimtopes_file(const std::string& path) {
  const std::string bytes = read_file_bytes(path);
  ByteReader r(path, bytes);
  char magic[8];
  for (char& c : magic) c = r.get<char>();
  if (std::memcmp(magic, kTrimtopesMagic, 8) != 0) r.fail("not a trimtopes file (wrong magic)");
  const uint32_t version = r.get<uint32_t>();
  if (version != kTrimtopesVersion) r.fail("unknown version " + std::to_string(version));
  r.get<uint32_t>();
  const uint64_t n = r.get<uint64_t>(), planes = r.get<uint64_t>(), tris = r.get<uint64_t>();
  // Every count against the file length before anything is allocated.
  const long double expect = 56.0L * n + 16 + 16.0L * planes + 36.0L * tris;
  if (n > (uint64_t(1) << 31) || expect != (long double)r.left())
    r.fail("counts (" + std::to_string(n) + " cells, " + std::to_string(planes) + " planes, " +
           std::to_string(tris) + " triangles) do not match the file length");
  RestTrimtopes t;
  t.particle.resize(n);
  for (auto& p : t.particle) {
    p = r.get<int32_t>();
    if (p < 0) r.fail("negative particle index");
  }
  t.site.resize(n);
  for (auto& s : t.site) s = get3(r);
  t.plane_start = read_offsets(r, n, planes, "plane");
  t.plane_normal.resize(planes);
  for (auto& m : t.plane_normal) m = get3(r);
  t.plane_offset.resize(planes);
  for (auto& d : t.plane_offset)
    if (d = r.get<float>(); !std::isfinite(d)) r.fail("a plane offset is not finite");
  t.tri_start = read_offsets(r, n, tris, "triangle");
  t.tri_vertex.resize(3 * tris);
  for (auto& v : t.tri_vertex) v = get3(r);
  t.box.resize(n);
  for (auto& b : t.box) {
    b.lo = get3(r);
    b.hi = get3(r);
  }
  return t;
}

}  // namespace pd
