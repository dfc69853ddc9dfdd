#include "host/fragments/tet_file.h"

#include <cmath>
#include <cstring>

#include "host/io/atomic_file.h"
#include "host/io/byte_file.h"

namespace pd {

namespace {

constexpr size_t kHeaderBytes = 32;

}  // namespace

void write_tets_file(const std::string& path, const EmbeddedTets& t) {
  const uint64_t vertices = t.vertices.size(), tets = t.tets.size();
  std::string out;
  out.reserve(kHeaderBytes + vertices * 12 + tets * 20);
  out.append(kTetsMagic, 8);
  put_bytes(out, kTetsVersion);
  put_bytes(out, uint32_t(0));
  put_bytes(out, vertices);
  put_bytes(out, tets);
  for (const Vec3d& v : t.vertices)
    for (double x : v) put_bytes(out, float(x));
  for (const auto& c : t.tets)
    for (int32_t k : c) put_bytes(out, k);
  for (int32_t p : t.particle) put_bytes(out, p);
  write_file_atomic(path, out);
}

EmbeddedTets read_tets_file(const std::string& path) {
  const std::string bytes = read_file_bytes(path);
  ByteReader r(path, bytes);
  char magic[8];
  for (char& c : magic) c = r.get<char>();
  if (std::memcmp(magic, kTetsMagic, 8) != 0) r.fail("not a tetrahedra file (wrong magic)");
  const uint32_t version = r.get<uint32_t>();
  if (version != kTetsVersion) r.fail("unknown version " + std::to_string(version));
  r.get<uint32_t>();
  const uint64_t vertices = r.get<uint64_t>(), tets = r.get<uint64_t>();
  // The counts against the file length before anything is allocated.
  const long double expect = 12.0L * vertices + 20.0L * tets;
  if (vertices > (uint64_t(1) << 31) || tets > (uint64_t(1) << 31) || expect != (long double)r.left())
    r.fail("counts (" + std::to_string(vertices) + " vertices, " + std::to_string(tets) +
           " tetrahedra) do not match the file length");
  EmbeddedTets t;
  t.vertices.resize(vertices);
  for (Vec3d& v : t.vertices)
    for (double& x : v)
      if (x = r.get<float>(); !std::isfinite(x)) r.fail("a vertex is not finite");
  t.tets.resize(tets);
  for (auto& c : t.tets)
    for (int32_t& k : c) {
      k = r.get<int32_t>();
      if (k < 0 || uint64_t(k) >= vertices) r.fail("vertex index " + std::to_string(k) + " out of range");
    }
  t.particle.resize(tets);
  for (int32_t& p : t.particle) {
    p = r.get<int32_t>();
    if (p < 0) r.fail("negative particle index");
  }
  return t;
}

}  // namespace pd
