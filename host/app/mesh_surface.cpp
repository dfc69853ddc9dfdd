#include "host/app/mesh_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pd {

namespace {

// The triangles at each vertex: tri[start[v] .. start[v + 1]) (counting sort).
struct VertexTriangles {
  std::vector<int64_t> start;
  std::vector<int32_t> tri;
};

VertexTriangles vertex_triangles(const CrackSurface& s) {
  VertexTriangles vt;
  vt.start.assign(s.vertices.size() + 1, 0);
  for (const auto& t : s.triangles)
    for (int32_t v : t) ++vt.start[size_t(v) + 1];
  for (size_t v = 0; v < s.vertices.size(); ++v) vt.start[v + 1] += vt.start[v];
  vt.tri.resize(size_t(vt.start.back()));
  std::vector<int64_t> fill(vt.start.begin(), vt.start.end() - 1);
  for (size_t f = 0; f < s.triangles.size(); ++f)
    for (int32_t v : s.triangles[f]) vt.tri[size_t(fill[size_t(v)]++)] = int32_t(f);
  return vt;
}

// Twice the area times the unit normal of triangle f.
Vec3d area_normal(const CrackSurface& s, size_t f) {
  const auto& t = s.triangles[f];
  const Vec3d& a = s.vertices[size_t(t[0])];
  return cross(s.vertices[size_t(t[1])] - a, s.vertices[size_t(t[2])] - a);
}

Vec3d unit(const Vec3d& a) {
  const double n = norm(a);
  return n > 0 ? (1 / n) * a : Vec3d{0, 0, 0};
}

Vec3 to_vec3(const Vec3d& v) {
  return {real(v[0]), real(v[1]), real(v[2])};
}

}  // namespace

std::vector<std::array<Vec3d, 3>> corner_normals(const CrackSurface& s, double crease_degrees) {
  const VertexTriangles vt = vertex_triangles(s);
  std::vector<Vec3d> face(s.triangles.size());
  for (size_t f = 0; f < face.size(); ++f) face[f] = area_normal(s, f);
  const double cos_crease = std::cos(crease_degrees * M_PI / 180);
  std::vector<std::array<Vec3d, 3>> out(s.triangles.size());
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    const Vec3d own = unit(face[f]);
    for (int c = 0; c < 3; ++c) {
      // The area-weighted sum over the triangles at this corner's vertex on the same surface
      // (original or crack) within the crease angle of this one, itself included.
      const size_t v = size_t(s.triangles[f][size_t(c)]);
      Vec3d sum{0, 0, 0};
      for (int64_t k = vt.start[v]; k < vt.start[v + 1]; ++k) {
        const size_t g = size_t(vt.tri[size_t(k)]);
        if (s.crack[g] != s.crack[f] || (g != f && dot(unit(face[g]), own) < cos_crease)) continue;
        sum = sum + face[g];
      }
      const Vec3d n = unit(sum);
      out[f][size_t(c)] = norm(n) > 0 ? n : own;
    }
  }
  return out;
}

void smooth_cracks(CrackSurface& s, int passes, double lambda, double mu) {
  if (passes <= 0) return;
  // Vertices on the original surface stay; the others move if crack triangles use them.
  const size_t nv = s.vertices.size();
  std::vector<uint8_t> fixed(nv, 0), on_crack(nv, 0);
  for (size_t f = 0; f < s.triangles.size(); ++f)
    for (int32_t v : s.triangles[f]) (s.crack[f] ? on_crack : fixed)[size_t(v)] = 1;
  // Neighbours along crack-triangle edges, each once.
  std::vector<std::vector<int32_t>> neighbours(nv);
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    if (!s.crack[f]) continue;
    for (int c = 0; c < 3; ++c) {
      const int32_t a = s.triangles[f][size_t(c)], b = s.triangles[f][size_t((c + 1) % 3)];
      for (const auto& [from, to] : {std::pair{a, b}, std::pair{b, a}}) {
        std::vector<int32_t>& list = neighbours[size_t(from)];
        if (std::find(list.begin(), list.end(), to) == list.end()) list.push_back(to);
      }
    }
  }
  std::vector<int32_t> moving;
  for (size_t v = 0; v < nv; ++v)
    if (on_crack[v] && !fixed[v] && !neighbours[v].empty()) moving.push_back(int32_t(v));
  // One Laplacian step of factor `step` for every moving vertex, all from the same positions.
  std::vector<Vec3d> next;
  auto step = [&](double factor) {
    next.resize(moving.size());
    for (size_t k = 0; k < moving.size(); ++k) {
      const std::vector<int32_t>& list = neighbours[size_t(moving[k])];
      Vec3d mean{0, 0, 0};
      for (int32_t w : list) mean = mean + s.vertices[size_t(w)];
      const Vec3d& x = s.vertices[size_t(moving[k])];
      next[k] = x + factor * ((1.0 / double(list.size())) * mean - x);
    }
    for (size_t k = 0; k < moving.size(); ++k) s.vertices[size_t(moving[k])] = next[k];
  };
  for (int pass = 0; pass < passes; ++pass) {
    step(lambda);
    step(mu);
  }
}

std::vector<uint8_t> covered_particles(const CrackSurface& s, const std::vector<int32_t>& body) {
  if (s.particle.size() != s.triangles.size())
    throw std::invalid_argument(
        "the crack mesh does not say which particle owns each face (written by an older perifrac): "
        "run again to write crack meshes with `property int particle`");
  const size_t n = body.size();
  std::vector<uint8_t> body_in_mesh;
  for (size_t f = 0; f < s.particle.size(); ++f) {
    const int32_t p = s.particle[f];
    if (p < 0 || size_t(p) >= n)
      throw std::invalid_argument("the crack mesh's face " + std::to_string(f) + " belongs to particle " +
                                  std::to_string(p) + " but the run has " + std::to_string(n) + " particles");
    const int32_t b = body[size_t(p)];
    if (b >= 0 && size_t(b) >= body_in_mesh.size()) body_in_mesh.resize(size_t(b) + 1, 0);
    if (b >= 0) body_in_mesh[size_t(b)] = 1;
  }
  std::vector<uint8_t> covered(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const int32_t b = body[i];
    covered[i] = b >= 0 && size_t(b) < body_in_mesh.size() && body_in_mesh[size_t(b)];
  }
  return covered;
}

void add_surface_triangles(const CrackSurface& s, const std::vector<std::array<Vec3d, 3>>& normals,
                           PrimitiveSet* prims, std::vector<Vec3>* albedo, std::vector<uint8_t>* material) {
  const bool materials = !material->empty();
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    const auto& t = s.triangles[f];
    const auto& n = normals[f];
    prims->add_triangle(to_vec3(s.vertices[size_t(t[0])]), to_vec3(s.vertices[size_t(t[1])]),
                        to_vec3(s.vertices[size_t(t[2])]), to_vec3(n[0]), to_vec3(n[1]), to_vec3(n[2]));
    const size_t owner = size_t(s.particle[f]);
    const Vec3 colour = (*albedo)[owner];
    albedo->push_back(colour);
    if (!materials) continue;
    const uint8_t surface = (*material)[owner];
    material->push_back(surface);
  }
}

}  // namespace pd
