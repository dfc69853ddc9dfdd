#include "host/geometry/collider_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "host/geometry/shapes.h"
#include "host/io/atomic_file.h"
#include "host/io/byte_file.h"

namespace pd {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A capsule along y: the profile of its two hemispheres and the side between them, revolved.
TriMesh capsule_mesh(double radius, double half_length, double edge) {
  const int arc = std::max(4, int(std::ceil(0.5 * kPi * radius / edge)));
  std::vector<std::array<double, 2>> profile;
  for (int k = 0; k <= arc; ++k) {  // the lower hemisphere, pole to equator
    const double a = -0.5 * kPi + 0.5 * kPi * k / arc;
    profile.push_back({radius * std::cos(a), -half_length + radius * std::sin(a)});
  }
  for (int k = 0; k <= arc; ++k) {  // the upper one, equator to pole
    const double a = 0.5 * kPi * k / arc;
    profile.push_back({radius * std::cos(a), half_length + radius * std::sin(a)});
  }
  profile.front()[0] = profile.back()[0] = 0;
  const int around = std::max(8, int(std::ceil(2 * kPi * radius / edge)));
  return revolve(profile, around, false, edge);
}

// A cylinder along y, revolved about its axis as colliders.h has it (cylinder_mesh centres its
// bounding box, which a polygon's corners make uneven).
TriMesh cylinder_along_y(double radius, double half_length, double edge) {
  const int across = std::max(1, int(std::ceil(radius / edge))),
            along = std::max(1, int(std::ceil(2 * half_length / edge)));
  std::vector<std::array<double, 2>> profile;
  for (int k = 0; k <= across; ++k) profile.push_back({radius * k / across, -half_length});
  for (int k = 1; k <= along; ++k) profile.push_back({radius, -half_length + 2 * half_length * k / along});
  for (int k = across - 1; k >= 0; --k) profile.push_back({radius * k / across, half_length});
  const int around = std::max(8, int(std::ceil(2 * kPi * radius / edge)));
  return revolve(profile, around, false, edge);
}

}  // namespace

TriMesh collider_mesh(const Collider& c, double edge, double plane_half) {
  const double x = double(c.size.x), y = double(c.size.y), z = double(c.size.z);
  switch (c.shape) {
    case kColliderSphere:
      return sphere_mesh(x, std::min(edge, x));
    case kColliderBox:
      return box_mesh({2 * x, 2 * y, 2 * z});
    case kColliderCapsule:
      return capsule_mesh(x, y, std::min(edge, x));
    case kColliderCylinder:
      return cylinder_along_y(x, y, std::min(edge, x));
    default: {  // a plane: the square facing +y
      TriMesh m;
      const double h = plane_half;
      m.vertices = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
      m.triangles = {{0, 2, 1}, {0, 3, 2}};
      return m;
    }
  }
}

TriMesh posed_mesh(const TriMesh& shape, const Collider& c) {
  TriMesh m = shape;
  const real* r = c.rotation;
  for (Vec3d& v : m.vertices) {
    const Vec3d q = v;
    v = {r[0] * q[0] + r[1] * q[1] + r[2] * q[2] + c.center.x,
         r[3] * q[0] + r[4] * q[1] + r[5] * q[2] + c.center.y,
         r[6] * q[0] + r[7] * q[1] + r[8] * q[2] + c.center.z};
  }
  return m;
}

void write_collider_obj(const std::vector<TriMesh>& shapes, const std::string& path) {
  std::string text = "# perifrac colliders, each in its own frame: colliders_NNNNN.csv poses them\n";
  size_t base = 1;
  char line[128];
  for (size_t k = 0; k < shapes.size(); ++k) {
    text += "o collider_" + std::to_string(k) + "\n";
    for (const Vec3d& v : shapes[k].vertices) {
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", v[0], v[1], v[2]);
      text += line;
    }
    for (const Triangle& t : shapes[k].triangles) {
      std::snprintf(line, sizeof line, "f %zu %zu %zu\n", base + size_t(t[0]), base + size_t(t[1]),
                    base + size_t(t[2]));
      text += line;
    }
    base += shapes[k].vertices.size();
  }
  write_file_atomic(path, text);
}

std::vector<TriMesh> read_collider_obj(const std::string& path) {
  std::istringstream in(read_file_bytes(path));
  std::vector<TriMesh> shapes;
  size_t base = 1;  // the file's index of the current object's first vertex
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag.empty() || tag[0] == '#') continue;
    auto fail = [&](const std::string& what) {
      throw MeshError(path, "line " + std::to_string(number) + ": " + what);
    };
    if (tag == "o") {
      if (!shapes.empty()) base += shapes.back().vertices.size();
      shapes.emplace_back();
    } else if (shapes.empty()) {
      fail("'" + tag + "' before the first object");
    } else if (tag == "v") {
      Vec3d v;
      if (!(words >> v[0] >> v[1] >> v[2])) fail("a vertex needs x y z");
      shapes.back().vertices.push_back(v);
    } else if (tag == "f") {
      Triangle t;
      for (int32_t& corner : t) {
        long long index = 0;
        if (!(words >> index)) fail("a face needs three vertex numbers");
        const long long local = index - (long long)base;
        if (local < 0 || local >= (long long)shapes.back().vertices.size())
          fail("a face's vertex is not of its object");
        corner = int32_t(local);
      }
      shapes.back().triangles.push_back(t);
    } else {
      fail("unknown line '" + tag + "'");
    }
  }
  return shapes;
}

}  // namespace pd
