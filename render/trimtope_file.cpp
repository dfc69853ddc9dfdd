#include "trimtope_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "../host/io/atomic_file.h"

namespace pd {

namespace {

constexpr size_t kHeaderBytes = 40;

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

void put3(std::string& out, const Vec3d& v) {
  for (double x : v) put(out, float(x));
}

// float32 of x rounded away from the box's inside (lo down, hi up).
float outward(double x, bool up) {
  float f = float(x);
  if (up && double(f) < x) f = std::nextafter(f, INFINITY);
  if (!up && double(f) > x) f = std::nextafter(f, -INFINITY);
  return f;
}

class Reader {
 public:
  Reader(const std::string& path, std::string bytes) : path_(path), bytes_(std::move(bytes)) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  Vec3d get3() {
    const float x = get<float>(), y = get<float>(), z = get<float>();
    return {x, y, z};
  }
  void need(size_t n) const {
    if (bytes_.size() - at_ < n) fail("truncated");
  }
  size_t left() const { return bytes_.size() - at_; }
  [[noreturn]] void fail(const std::string& why) const { throw io_error("read", path_, why); }

 private:
  std::string path_;
  std::string bytes_;
  size_t at_ = 0;
};

// Reads a CSR offset array of n + 1 entries that must start at 0, never decrease and end at
// `total`.
std::vector<int64_t> read_offsets(Reader& r, uint64_t n, uint64_t total, const char* what) {
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
  put(out, kTrimtopesVersion);
  put(out, uint32_t(0));
  put(out, n);
  put(out, planes);
  put(out, tris);
  for (int32_t p : t.particle) put(out, p);
  for (const Vec3d& s : t.site) put3(out, s);
  for (int64_t o : t.plane_start) put(out, o);
  for (const Vec3d& m : t.plane_normal) put3(out, m);
  for (double d : t.plane_offset) put(out, float(d));
  for (int64_t o : t.tri_start) put(out, o);
  for (const Vec3d& v : t.tri_vertex) put3(out, v);
  for (const Box3d& b : t.box) {
    for (double x : b.lo) put(out, outward(x, false));
    for (double x : b.hi) put(out, outward(x, true));
  }
  write_file_atomic(path, out);
}

RestTrimtopes read_trimtopes_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error("read", path, "cannot open");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Reader r(path, std::move(bytes));
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
  for (auto& s : t.site) s = r.get3();
  t.plane_start = read_offsets(r, n, planes, "plane");
  t.plane_normal.resize(planes);
  for (auto& m : t.plane_normal) m = r.get3();
  t.plane_offset.resize(planes);
  for (auto& d : t.plane_offset) d = r.get<float>();
  t.tri_start = read_offsets(r, n, tris, "triangle");
  t.tri_vertex.resize(3 * tris);
  for (auto& v : t.tri_vertex) v = r.get3();
  t.box.resize(n);
  for (auto& b : t.box) {
    b.lo = r.get3();
    b.hi = r.get3();
  }
  return t;
}

}  // namespace pd
