#include "host/geometry/collider_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "host/geometry/shapes.h"

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

}  // namespace pd
