#include "host/geometry/shapes.h"

#include <algorithm>
#include <cmath>
#include <map>

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

std::vector<int> ring_segments(const Profile& profile, int segments, bool periodic, double edge) {
  std::vector<int> count(profile.size());
  for (size_t k = 0; k < profile.size(); ++k) {
    const double r = profile[k][0];
    if (!periodic && r == 0)
      count[k] = 1;  // a pole
    else if (edge > 0)
      count[k] = std::clamp(int(std::ceil(2 * kPi * r / edge)), std::min(6, segments), segments);
    else
      count[k] = segments;
  }
  return count;
}

TriMesh revolve(const Profile& profile, int segments, bool periodic, double edge) {
  TriMesh mesh;
  const size_t n = profile.size();
  const std::vector<int> count = ring_segments(profile, segments, periodic, edge);
  std::vector<int32_t> first(n);  // first vertex of each ring; a pole is one vertex
  for (size_t k = 0; k < n; ++k) {
    first[k] = int32_t(mesh.vertices.size());
    for (int s = 0; s < count[k]; ++s) {
      const double a = 2 * kPi * s / count[k];
      mesh.vertices.push_back({profile[k][0] * std::cos(a), profile[k][1], -profile[k][0] * std::sin(a)});
    }
  }
  auto at = [&](size_t k, int s) { return first[k] + s % count[k]; };
  const size_t bands = periodic ? n : n - 1;
  for (size_t k = 0; k < bands; ++k) {
    const size_t k1 = (k + 1) % n;
    const int m0 = count[k], m1 = count[k1];
    if (m0 == m1 || m0 == 1 || m1 == 1) {
      // Equal rings (quads split along one diagonal), or a fan around a pole.
      for (int s = 0; s < std::max(m0, m1); ++s) {
        const int32_t a = at(k, s), b = at(k, s + 1), c = at(k1, s + 1), d = at(k1, s);
        if (m0 > 1) mesh.triangles.push_back({a, b, c});
        if (m1 > 1) mesh.triangles.push_back({a, c, d});
      }
      continue;
    }
    // Rings of different counts: walk both by angle, always advancing the one whose next
    // point comes first (compared exactly as i / m0 against j / m1).
    for (int i = 0, j = 0; i < m0 || j < m1;) {
      if (j == m1 || (i < m0 && int64_t(i + 1) * m1 <= int64_t(j + 1) * m0)) {
        mesh.triangles.push_back({at(k, i), at(k, i + 1), at(k1, j)});
        ++i;
      } else {
        mesh.triangles.push_back({at(k, i), at(k1, j + 1), at(k1, j)});
        ++j;
      }
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
  // A geodesic sphere: each face of an icosahedron cut into f^2 triangles, projected outward.
  // The triangles are nearly equilateral everywhere (a latitude-longitude mesh has slivers at
  // its poles, where TetGen's quality refinement stalls).
  const double t = 0.5 * (1 + std::sqrt(5.0));
  const Vec3d corner[12] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  const int face[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  // Edge of the icosahedron inscribed in the unit sphere: 1 / sin(2 pi / 5).
  const int f = int(std::clamp(std::ceil(1.0515 * radius / edge), 2.0, 256.0));
  TriMesh mesh;
  // Points shared by faces (on edges and corners) are found by their weights on the corners.
  std::map<std::array<int, 6>, int32_t> shared;
  auto point = [&](const int* c, int i, int j) {
    const int w[3] = {f - i - j, i, j};
    std::array<int, 6> key{-1, 0, -1, 0, -1, 0};
    int used = 0;
    for (int a = 0; a < 3; ++a)
      if (w[a] > 0) key[size_t(2 * used)] = c[a], key[size_t(2 * used + 1)] = w[a], ++used;
    // Canonical order of the (corner, weight) pairs.
    for (int a = 0; a < used; ++a)
      for (int b = a + 1; b < used; ++b)
        if (key[size_t(2 * b)] < key[size_t(2 * a)]) {
          std::swap(key[size_t(2 * a)], key[size_t(2 * b)]);
          std::swap(key[size_t(2 * a + 1)], key[size_t(2 * b + 1)]);
        }
    const bool interior = used == 3;
    if (!interior) {
      const auto it = shared.find(key);
      if (it != shared.end()) return it->second;
    }
    Vec3d p{0, 0, 0};
    for (int a = 0; a < 3; ++a) p = p + double(w[a]) * corner[c[a]];
    mesh.vertices.push_back((radius / norm(p)) * p);
    const int32_t id = int32_t(mesh.vertices.size() - 1);
    if (!interior) shared.emplace(key, id);
    return id;
  };
  std::vector<int32_t> row((size_t(f) + 1) * (size_t(f) + 2) / 2);
  for (const auto& c : face) {
    auto index = [&](int i, int j) { return size_t(i) * (size_t(2 * f) + 3 - size_t(i)) / 2 + size_t(j); };
    for (int i = 0; i <= f; ++i)
      for (int j = 0; i + j <= f; ++j) row[index(i, j)] = point(c, i, j);
    for (int i = 0; i < f; ++i)
      for (int j = 0; i + j < f; ++j) {
        mesh.triangles.push_back({row[index(i, j)], row[index(i + 1, j)], row[index(i, j + 1)]});
        if (i + j + 1 < f)
          mesh.triangles.push_back({row[index(i + 1, j)], row[index(i + 1, j + 1)], row[index(i, j + 1)]});
      }
  }
  return finish(std::move(mesh));
}

TriMesh cylinder_mesh(double radius, double height, double edge) {
  Profile p{{0, -0.5 * height}};
  line_to(p, {radius, -0.5 * height}, edge);
  line_to(p, {radius, 0.5 * height}, edge);
  line_to(p, {0, 0.5 * height}, edge);
  return finish(revolve(p, segments_for(radius, edge), false, edge));
}

TriMesh torus_mesh(double radius, double tube_radius, double edge) {
  const int around = segments_for(tube_radius, edge);
  Profile p;
  for (int k = 0; k < around; ++k) {
    const double a = 2 * kPi * k / around;
    p.push_back({radius + tube_radius * std::cos(a), tube_radius * std::sin(a)});
  }
  return finish(revolve(p, segments_for(radius + tube_radius, edge), true, edge));
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
  return finish(revolve(p, segments_for(radius, edge), false, edge));
}

TriMesh vase_sheet(double radius, double height, double edge) {
  Profile p;
  vase_outer_surface(p, radius, height, edge);
  // Orient as the closed vase's outer surface: normals away from the axis.
  TriMesh sheet = revolve(p, segments_for(radius, edge), false, edge);
  TriMesh closed = sheet;
  const int32_t lid = int32_t(closed.vertices.size());
  closed.vertices.push_back({0, p.back()[1], 0});
  const int segments = ring_segments(p, segments_for(radius, edge), false, edge).back();
  const int32_t rim = lid - segments;
  for (int s = 0; s < segments; ++s) closed.triangles.push_back({rim + s, rim + (s + 1) % segments, lid});
  if (signed_volume(closed) < 0) flip_orientation(sheet);
  transform(sheet, 1, -1.0 * bounds(closed).center());
  return sheet;
}

}  // namespace pd
