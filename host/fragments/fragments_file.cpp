#include "host/fragments/fragments_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <ostream>
#include <sstream>

#include "host/io/atomic_file.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, ".pfg files are little endian");

namespace pd {

namespace {

// One record as stored: packed, little endian, 280 bytes.
#pragma pack(push, 1)
struct Record {
  int32_t id, particles;
  double mass;
  double rest_centroid[3], centroid[3];
  double quaternion[4];  // w x y z, w >= 0: the transform to render with
  double matrix[9];      // the same rotation, row major
  double translation[3];
  double fit_quaternion[4];  // the least-squares fit
  double fit_translation[3];
  double rms, radius, residual, blend;
};
#pragma pack(pop)
static_assert(sizeof(Record) == kFragmentRecordBytes);

// Quaternion w x y z with w >= 0 (the pair q, -q is one rotation; this picks one).
void put_quaternion(const Eigen::Matrix3d& r, double* out) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
}

Eigen::Matrix3d get_quaternion(const double* in) {
  return Eigen::Quaterniond(in[0], in[1], in[2], in[3]).normalized().toRotationMatrix();
}

void put3(const Eigen::Vector3d& v, double* out) {
  out[0] = v.x(), out[1] = v.y(), out[2] = v.z();
}
Eigen::Vector3d get3(const double* in) {
  return {in[0], in[1], in[2]};
}

Record to_record(const Fragment& f) {
  Record r;
  r.id = f.id;
  r.particles = f.particles;
  r.mass = f.fit.mass;
  put3(f.fit.rest_centroid, r.rest_centroid);
  put3(f.fit.centroid, r.centroid);
  put_quaternion(f.rotation, r.quaternion);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) r.matrix[3 * a + b] = f.rotation(a, b);
  put3(f.translation, r.translation);
  put_quaternion(f.fit.rotation, r.fit_quaternion);
  put3(f.fit.translation, r.fit_translation);
  r.rms = f.fit.rms;
  r.radius = f.fit.radius;
  r.residual = f.fit.residual();
  r.blend = f.blend;
  return r;
}

Fragment from_record(const Record& r) {
  Fragment f;
  f.id = r.id;
  f.particles = r.particles;
  f.fit.mass = r.mass;
  f.fit.rest_centroid = get3(r.rest_centroid);
  f.fit.centroid = get3(r.centroid);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) f.rotation(a, b) = r.matrix[3 * a + b];
  f.translation = get3(r.translation);
  f.fit.rotation = get_quaternion(r.fit_quaternion);
  f.fit.translation = get3(r.fit_translation);
  f.fit.rms = r.rms;
  f.fit.radius = r.radius;
  f.blend = r.blend;
  return f;
}

template <class T>
void put(std::ostream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

template <class T>
T get(const std::string& bytes, size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof value);
  return value;
}

}  // namespace

std::string fragments_file_name(int64_t frame) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%05lld", static_cast<long long>(frame));
  return "fragments_" + std::string(digits) + ".pfg";
}

void write_fragments_file(const std::string& path, int64_t frame, int64_t step, double time,
                          const std::vector<Fragment>& fragments) {
  write_file_atomic(path, [&](std::ostream& out) {
    // Header.
    out.write(kFragmentsMagic, sizeof kFragmentsMagic);
    put(out, kFragmentsVersion);
    put(out, uint32_t(kFragmentRecordBytes));
    put(out, uint64_t(fragments.size()));
    put(out, frame);
    put(out, step);
    put(out, time);
    // Records, converted a block at a time.
    const size_t block = 1 << 12;
    std::vector<Record> buffer(block);
    for (size_t first = 0; first < fragments.size(); first += block) {
      const size_t count = std::min(block, fragments.size() - first);
      for (size_t k = 0; k < count; ++k) buffer[k] = to_record(fragments[first + k]);
      out.write(reinterpret_cast<const char*>(buffer.data()), std::streamsize(count * sizeof(Record)));
    }
  });
}

FragmentsFrame read_fragments_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error_errno("read", path, errno);
  std::ostringstream all;
  all << in.rdbuf();
  const std::string bytes = all.str();

  // Header: magic, version, record size, count against the file length.
  if (bytes.size() < kFragmentsHeaderBytes)
    throw io_error("read", path,
                   "truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the header");
  if (std::memcmp(bytes.data(), kFragmentsMagic, sizeof kFragmentsMagic) != 0)
    throw io_error("read", path, "not a fragments file (bad magic)");
  const auto version = get<uint32_t>(bytes, 8);
  if (version != kFragmentsVersion)
    throw io_error("read", path, "unknown version " + std::to_string(version));
  const auto record = get<uint32_t>(bytes, 12);
  if (record != kFragmentRecordBytes)
    throw io_error(
        "read", path,
        "record size " + std::to_string(record) + ", expected " + std::to_string(kFragmentRecordBytes));
  const auto count = get<uint64_t>(bytes, 16);
  const size_t room = (bytes.size() - kFragmentsHeaderBytes) / kFragmentRecordBytes;
  if (count > room || bytes.size() != kFragmentsHeaderBytes + count * kFragmentRecordBytes)
    throw io_error("read", path,
                   "file length " + std::to_string(bytes.size()) + " does not match " +
                       std::to_string(count) + " fragments");

  FragmentsFrame f;
  f.frame = get<int64_t>(bytes, 24);
  f.step = get<int64_t>(bytes, 32);
  f.time = get<double>(bytes, 40);
  f.fragments.reserve(count);
  for (size_t k = 0; k < count; ++k) {
    const Record r = get<Record>(bytes, kFragmentsHeaderBytes + k * kFragmentRecordBytes);
    // (The record's numbers after its two integers are doubles: a pose that is not finite is damage.)
    double numbers[(sizeof(Record) - 8) / 8];
    std::memcpy(numbers, reinterpret_cast<const char*>(&r) + 8, sizeof numbers);
    for (double x : numbers)
      if (!std::isfinite(x))
        throw io_error("read", path, "fragment " + std::to_string(k) + " has a number that is not finite");
    f.fragments.push_back(from_record(r));
  }
  return f;
}

}  // namespace pd
