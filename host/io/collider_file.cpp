#include "host/io/collider_file.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "host/io/atomic_file.h"

namespace pd {
namespace {

constexpr const char* kHeader =
    "frame,time,collider,shape,law,size_x,size_y,size_z,center_x,center_y,center_z,qw,qx,qy,qz,"
    "velocity_x,velocity_y,velocity_z,omega_x,omega_y,omega_z,mass";
constexpr int kColumns = 22;
constexpr const char* kShapeNames[] = {"plane", "sphere", "box", "capsule", "cylinder", "mesh"};
constexpr const char* kLawNames[] = {"penalty", "lammps_indent"};

template <size_t N>
int index_of(const char* const (&names)[N], const std::string& name) {
  for (size_t i = 0; i < N; ++i)
    if (name == names[i]) return int(i);
  return -1;
}

}  // namespace

std::string colliders_file_name(int64_t frame) {
  char name[48];
  std::snprintf(name, sizeof name, "colliders_%05lld.csv", static_cast<long long>(frame));
  return name;
}

std::array<double, 4> rotation_to_quaternion(const real* m) {
  // Shepperd's method: from the largest of w, x, y, z, so no division by a small number.
  const double trace = double(m[0]) + double(m[4]) + double(m[8]);
  std::array<double, 4> q;
  if (trace > double(m[0]) && trace > double(m[4]) && trace > double(m[8])) {
    const double s = 2 * std::sqrt(1 + trace);
    q = {0.25 * s, (m[7] - m[5]) / s, (m[2] - m[6]) / s, (m[3] - m[1]) / s};
  } else if (m[0] >= m[4] && m[0] >= m[8]) {
    const double s = 2 * std::sqrt(1 + double(m[0]) - m[4] - m[8]);
    q = {(m[7] - m[5]) / s, 0.25 * s, (m[1] + m[3]) / s, (m[2] + m[6]) / s};
  } else if (m[4] >= m[8]) {
    const double s = 2 * std::sqrt(1 + double(m[4]) - m[0] - m[8]);
    q = {(m[2] - m[6]) / s, (m[1] + m[3]) / s, 0.25 * s, (m[5] + m[7]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + double(m[8]) - m[0] - m[4]);
    q = {(m[3] - m[1]) / s, (m[2] + m[6]) / s, (m[5] + m[7]) / s, 0.25 * s};
  }
  if (q[0] < 0)
    for (double& c : q) c = -c;  // one sign for the same turn
  return q;
}

void quaternion_to_rotation(const std::array<double, 4>& in, real* m) {
  const double n = std::sqrt(in[0] * in[0] + in[1] * in[1] + in[2] * in[2] + in[3] * in[3]);
  const double w = in[0] / n, x = in[1] / n, y = in[2] / n, z = in[3] / n;
  const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                       2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                       2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
  for (int i = 0; i < 9; ++i) m[i] = real(r[i]);
}

void write_colliders_file(const std::string& path, int64_t frame, double time,
                          const std::vector<ColliderState>& colliders) {
  std::string text = std::string(kHeader) + "\n";
  char row[768];
  for (size_t k = 0; k < colliders.size(); ++k) {
    const Collider& c = colliders[k].collider;
    const std::array<double, 4> q = rotation_to_quaternion(c.rotation);
    std::snprintf(
        row, sizeof row,
        "%lld,%.9g,%zu,%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,"
        "%.9g,%.9g\n",
        static_cast<long long>(frame), time, k, kShapeNames[c.shape <= kColliderMesh ? c.shape : 0],
        kLawNames[c.law <= 1 ? c.law : 0], double(c.size.x), double(c.size.y), double(c.size.z),
        double(c.center.x), double(c.center.y), double(c.center.z), q[0], q[1], q[2], q[3],
        double(c.velocity.x), double(c.velocity.y), double(c.velocity.z), double(c.omega.x),
        double(c.omega.y), double(c.omega.z), colliders[k].mass);
    text += row;
  }
  write_file_atomic(path, text);
}

std::vector<ColliderState> read_colliders_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw io_error_errno("read", path, errno);
  std::string line;
  if (!std::getline(in, line) || line != kHeader)
    throw io_error("read", path, "line 1 is not the colliders header");
  std::vector<ColliderState> out;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    const std::string where = "line " + std::to_string(number) + ": ";
    if (int(cells.size()) != kColumns)
      throw io_error("read", path,
                     where + std::to_string(cells.size()) + " values, expected " + std::to_string(kColumns));
    double v[kColumns] = {};
    for (int i = 0; i < kColumns; ++i) {
      if (i == 3 || i == 4) continue;
      char* end = nullptr;
      v[i] = std::strtod(cells[size_t(i)].c_str(), &end);
      if (end == cells[size_t(i)].c_str() || *end != '\0' || !std::isfinite(v[i]))
        throw io_error("read", path, where + "'" + cells[size_t(i)] + "' is not a finite number");
    }
    const int shape = index_of(kShapeNames, cells[3]), law = index_of(kLawNames, cells[4]);
    if (shape < 0) throw io_error("read", path, where + "unknown shape '" + cells[3] + "'");
    if (law < 0) throw io_error("read", path, where + "unknown law '" + cells[4] + "'");
    ColliderState s;
    Collider& c = s.collider;
    c.shape = uint8_t(shape);
    c.law = uint8_t(law);
    c.size = {real(v[5]), real(v[6]), real(v[7])};
    c.center = {real(v[8]), real(v[9]), real(v[10])};
    if (v[11] == 0 && v[12] == 0 && v[13] == 0 && v[14] == 0)
      throw io_error("read", path, where + "the rotation quaternion is zero");
    quaternion_to_rotation({v[11], v[12], v[13], v[14]}, c.rotation);
    c.velocity = {real(v[15]), real(v[16]), real(v[17])};
    c.omega = {real(v[18]), real(v[19]), real(v[20])};
    s.mass = v[21];
    out.push_back(s);
  }
  return out;
}

}  // namespace pd
