#include "host/geometry/tri_mesh.h"

#include <utility>

namespace pd {

MeshError::MeshError(std::string path, const std::string& message)
    : std::invalid_argument(path + ": " + message), path_(std::move(path)) {}

double signed_volume(const TriMesh& mesh) {
  // Relative to the bounding-box centre, which keeps round-off small for meshes far from the origin.
  const Vec3d o = bounds(mesh).center();
  double six_v = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3d a = mesh.vertices[t[0]] - o, b = mesh.vertices[t[1]] - o, c = mesh.vertices[t[2]] - o;
    six_v += dot(a, cross(b, c));
  }
  return six_v / 6;
}

double triangle_area(const TriMesh& mesh, size_t t) {
  const Triangle& f = mesh.triangles[t];
  const Vec3d& a = mesh.vertices[f[0]];
  return 0.5 * norm(cross(mesh.vertices[f[1]] - a, mesh.vertices[f[2]] - a));
}

double surface_area(const TriMesh& mesh) {
  double area = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) area += triangle_area(mesh, t);
  return area;
}

Box3d bounds(const TriMesh& mesh) {
  Box3d box;
  for (const Vec3d& v : mesh.vertices) box.add(v);
  return box;
}

void transform(TriMesh& mesh, double scale, const Vec3d& offset) {
  for (Vec3d& v : mesh.vertices) v = scale * v + offset;
}

void flip_orientation(TriMesh& mesh) {
  for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
}

void append(TriMesh& mesh, const TriMesh& other) {
  const int32_t base = int32_t(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Triangle& t : other.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

double segment_hits(const Vec3d& a, const Vec3d& b, const Vec3d& p, const Vec3d& q, const Vec3d& r) {
  const Vec3d dir = b - a, e1 = q - p, e2 = r - p;
  const Vec3d h = cross(dir, e2);
  const double det = dot(e1, h);
  if (det == 0) return -1;
  const double inv = 1 / det;
  const Vec3d s = a - p;
  const double u = inv * dot(s, h);
  if (u < 0 || u > 1) return -1;
  const Vec3d qv = cross(s, e1);
  const double v = inv * dot(dir, qv);
  if (v < 0 || u + v > 1) return -1;
  const double t = inv * dot(e2, qv);
  return t > 0 && t < 1 ? t : -1;
}

}  // namespace pd
