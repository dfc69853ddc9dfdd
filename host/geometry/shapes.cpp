#include "shapes.h"

#include <algorithm>
#include <cmath>

namespace pd {

namespace {

constexpr double kPi = 3.14159265358979323846;
using Profile = std::vector<std::array<double, 2>>;

// Points around a circle of radius r: about one per `edge`, at least 12 and at most 1024 (so a
// tiny spacing cannot make a huge mesh before the particle budget is checked).
constexpr double kMaxPieces = 1024;
int segments_for(double r, double edge) {
  return int(std::clamp(std::ceil(2 * kPi * r / edge), 12.0, kMaxPieces));
}

// Appends the straight segment to `b` (excluded: `a` is already in the profile) in steps <= edge.
void line_to(Profile& p, std::array<double, 2> b, double edge) {
  const std::array<double, 2> a = p.back();
  const int n = int(std::clamp(std::ceil(std::hypot(b[0] - a[0], b[1] - a[1]) / edge), 1.0, kMaxPieces));
  for (int k = 1; k <= n; ++k) {
    const double s = double(k) / n;
    p.push_back({a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])});
  }
}

// Vase outer radius at height fraction t in [0, 1], relative to the widest radius: cosine
// blends between control points (base 0.55, belly 1 at 0.35, neck 0.45 at 0.8, lip 0.6).
double vase_radius(double t) {
  static const double knots[4][2] = {{0.0, 0.55}, {0.35, 1.0}, {0.8, 0.45}, {1.0, 0.6}};
  int k = 0;
  while (k < 2 && t > knots[k + 1][0]) ++k;
  const double s = (t - knots[k][0]) / (knots[k + 1][0] - knots[k][0]);
  return knots[k][1] + (knots[k + 1][1] - knots[k][1]) * 0.5 * (1 - std::cos(kPi * s));
}

// Outer surface from the axis at the bottom: the base, a rounded foot (a quarter circle of
// radius `foot`, so the surface can be thickened inward), and the wall up to the lip.
void vase_outer_surface(Profile& p, double radius, double height, double edge) {
  const double y0 = -0.5 * height, r0 = radius * vase_radius(0), foot = vase_foot(radius, height);
  p.push_back({0, y0});
  line_to(p, {r0 - foot, y0}, edge);
  const int arc = int(std::clamp(std::ceil(0.5 * kPi * foot / edge), 4.0, kMaxPieces));
  for (int k = 1; k <= arc; ++k) {
    const double a = 0.5 * kPi * k / arc;
    p.push_back({r0 - foot + foot * std::sin(a), y0 + foot - foot * std::cos(a)});
  }
  const int n = int(std::clamp(std::ceil(1.5 * height / edge), 8.0, kMaxPieces));
  const double t0 = foot / height;
  for (int k = 1; k <= n; ++k) {
    const double t = t0 + (1 - t0) * double(k) / n;
    p.push_back({radius * vase_radius(t) + r0 - radius * vase_radius(t0), y0 + t * height});
  }
}

// Closed shapes: bounding-box centre moved to the origin, triangles flipped to face outward
// when the signed volume is negative.
TriMesh finish(TriMesh mesh) {
  transform(mesh, 1, -1.0 * bounds(mesh).center());
  if (signed_volume(mesh) < 0) flip_orientation(mesh);
  return mesh;
}

}  // namespace

double vase_foot(double radius, double height) {
  return std::min(0.25 * radius, 0.1 * height);
}

TriMesh revolve(const Profile& profile, int segments, bool periodic) {
  TriMesh mesh;
  const size_t n = profile.size();
  std::vector<int32_t> first(n);  // first vertex of each ring; a pole is one vertex
  std::vector<bool> pole(n);
  for (size_t k = 0; k < n; ++k) {
    first[k] = int32_t(mesh.vertices.size());
    pole[k] = !periodic && profile[k][0] == 0;
    const int count = pole[k] ? 1 : segments;
    for (int s = 0; s < count; ++s) {
      const double a = 2 * kPi * s / segments;
      mesh.vertices.push_back({profile[k][0] * std::cos(a), profile[k][1], -profile[k][0] * std::sin(a)});
    }
  }
  auto at = [&](size_t k, int s) { return pole[k] ? first[k] : first[k] + (s % segments); };
  const size_t bands = periodic ? n : n - 1;
  for (size_t k = 0; k < bands; ++k) {
    const size_t k1 = (k + 1) % n;
    for (int s = 0; s < segments; ++s) {
      const int32_t a = at(k, s), b = at(k, s + 1), c = at(k1, s + 1), d = at(k1, s);
      if (!pole[k]) mesh.triangles.push_back({a, b, c});
      if (!pole[k1]) mesh.triangles.push_back({a, c, d});
    }
  }
  return mesh;
}

TriMesh box_mesh(const Vec3d& size) {
  TriMesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.vertices.push_back(
        {(k & 1 ? 0.5 : -0.5) * size[0], (k & 2 ? 0.5 : -0.5) * size[1], (k & 4 ? 0.5 : -0.5) * size[2]});
  // Faces as corner quads (bit 0 = +x, bit 1 = +y, bit 2 = +z), counter-clockwise from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

TriMesh sphere_mesh(double radius, double edge) {
  const int segments = segments_for(radius, edge);
  const int rings = std::max(6, segments / 2);
  Profile p;
  for (int k = 0; k <= rings; ++k) {
    const double a = kPi * k / rings;
    p.push_back({k == 0 || k == rings ? 0.0 : radius * std::sin(a), -radius * std::cos(a)});
  }
  return finish(revolve(p, segments, false));
}

TriMesh cylinder_mesh(double radius, double height, double edge) {
  Profile p{{0, -0.5 * height}};
  line_to(p, {radius, -0.5 * height}, edge);
  line_to(p, {radius, 0.5 * height}, edge);
  line_to(p, {0, 0.5 * height}, edge);
  return finish(revolve(p, segments_for(radius, edge), false));
}

TriMesh torus_mesh(double radius, double tube_radius, double edge) {
  const int around = segments_for(tube_radius, edge);
  Profile p;
  for (int k = 0; k < around; ++k) {
    const double a = 2 * kPi * k / around;
    p.push_back({radius + tube_radius * std::cos(a), tube_radius * std::sin(a)});
  }
  return finish(revolve(p, segments_for(radius + tube_radius, edge), true));
}

TriMesh vase_mesh(double radius, double height, double wall, double edge) {
  // Profile: the outer surface, across the lip, then the inner surface (the outer one moved in
  // by `wall`: the wall, the foot's arc of radius foot - wall, the floor) back to the axis.
  const double y0 = -0.5 * height, foot = vase_foot(radius, height), r0 = radius * vase_radius(0);
  Profile p;
  vase_outer_surface(p, radius, height, edge);
  const double t0 = foot / height, shift = r0 - radius * vase_radius(t0);
  const int n = int(std::clamp(std::ceil(1.5 * height / edge), 8.0, kMaxPieces));
  for (int k = n; k >= 0; --k) {
    const double t = t0 + (1 - t0) * double(k) / n;
    const Profile::value_type q{radius * vase_radius(t) + shift - wall, y0 + t * height};
    if (k == n)
      line_to(p, q, edge);
    else
      p.push_back(q);
  }
  const double inner = foot - wall;
  const int arc = int(std::clamp(std::ceil(0.5 * kPi * inner / edge), 4.0, kMaxPieces));
  for (int k = arc - 1; k >= 0; --k) {
    const double a = 0.5 * kPi * k / arc;
    p.push_back({r0 - foot + inner * std::sin(a), y0 + foot - inner * std::cos(a)});
  }
  line_to(p, {0, y0 + wall}, edge);
  return finish(revolve(p, segments_for(radius, edge), false));
}

TriMesh vase_sheet(double radius, double height, double edge) {
  Profile p;
  vase_outer_surface(p, radius, height, edge);
  // Orient as the closed vase's outer surface: normals away from the axis.
  TriMesh sheet = revolve(p, segments_for(radius, edge), false);
  TriMesh closed = revolve(p, segments_for(radius, edge), false);
  const int32_t lid = int32_t(closed.vertices.size());
  closed.vertices.push_back({0, p.back()[1], 0});
  const int segments = segments_for(radius, edge);
  const int32_t rim = lid - segments;
  for (int s = 0; s < segments; ++s) closed.triangles.push_back({rim + s, rim + (s + 1) % segments, lid});
  if (signed_volume(closed) < 0) flip_orientation(sheet);
  transform(sheet, 1, -1.0 * bounds(closed).center());
  return sheet;
}

}  // namespace pd
