#include "host/fragments/element_complex.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace pd {

void ElementComplex::begin_element(int32_t p) {
  particle.push_back(p);
  corner_start.push_back(corner_start.back());
  face_start.push_back(face_start.back());
}

int32_t ElementComplex::add_corner(int32_t v) {
  if (corner_vertex.size() >= size_t(std::numeric_limits<int32_t>::max()))
    throw std::length_error("ElementComplex: more than 2^31 corners");
  corner_vertex.push_back(v);
  ++corner_start.back();
  return int32_t(corner_vertex.size() - 1);
}

void ElementComplex::add_face(const int32_t* corners, size_t count, int32_t other) {
  face_corner.insert(face_corner.end(), corners, corners + count);
  face_corner_start.push_back(int64_t(face_corner.size()));
  face_other.push_back(other);
  ++face_start.back();
}

ElementComplex assemble(size_t particles, std::vector<ElementComplex> parts) {
  // Where each particle's element is: (part, element in it).
  std::vector<std::pair<int32_t, int32_t>> where(particles, {-1, -1});
  for (size_t k = 0; k < parts.size(); ++k)
    for (size_t e = 0; e < parts[k].size(); ++e) {
      const int32_t p = parts[k].particle[e];
      if (p < 0 || size_t(p) >= particles)
        throw std::invalid_argument("an element stands for particle " + std::to_string(p) + " (allowed: 0.." +
                                    std::to_string(particles) + ")");
      if (where[size_t(p)].first >= 0)
        throw std::invalid_argument("particle " + std::to_string(p) + " has two elements");
      where[size_t(p)] = {int32_t(k), int32_t(e)};
    }

  // Vertices part after part; elements in particle order, corners and faces renumbered.
  ElementComplex out;
  std::vector<int64_t> vertex_base(parts.size() + 1, 0);
  for (size_t k = 0; k < parts.size(); ++k) {
    vertex_base[k + 1] = vertex_base[k] + int64_t(parts[k].vertices.size());
    out.vertices.insert(out.vertices.end(), parts[k].vertices.begin(), parts[k].vertices.end());
  }
  if (vertex_base.back() > std::numeric_limits<int32_t>::max())
    throw std::length_error("ElementComplex: more than 2^31 vertices");
  for (size_t p = 0; p < particles; ++p) {
    if (where[p].first < 0) throw std::invalid_argument("particle " + std::to_string(p) + " has no element");
    const ElementComplex& c = parts[size_t(where[p].first)];
    const size_t e = size_t(where[p].second);
    const int32_t base = int32_t(vertex_base[size_t(where[p].first)]);
    out.begin_element(int32_t(p));
    const int64_t first_corner = c.corner_start[e];
    const int32_t new_first = int32_t(out.corner_vertex.size());
    for (int64_t k = first_corner; k < c.corner_start[e + 1]; ++k)
      out.add_corner(base + c.corner_vertex[size_t(k)]);
    for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f) {
      const int64_t b = c.face_corner_start[size_t(f)], end = c.face_corner_start[size_t(f) + 1];
      for (int64_t k = b; k < end; ++k)
        out.face_corner.push_back(new_first + int32_t(c.face_corner[size_t(k)] - first_corner));
      out.face_corner_start.push_back(int64_t(out.face_corner.size()));
      out.face_other.push_back(c.face_other[size_t(f)]);
      ++out.face_start.back();
    }
  }
  return out;
}

void check(const ElementComplex& c, size_t particles) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("element complex: " + what); };
  const size_t n = c.size();
  if (c.corner_start.size() != n + 1 || c.face_start.size() != n + 1 ||
      c.face_corner_start.size() != c.faces() + 1 ||
      size_t(c.corner_start.back()) != c.corner_vertex.size() || size_t(c.face_start.back()) != c.faces() ||
      size_t(c.face_corner_start.back()) != c.face_corner.size())
    fail("inconsistent array sizes");
  std::vector<int32_t> seen;
  for (size_t e = 0; e < n; ++e) {
    if (c.particle[e] < 0 || size_t(c.particle[e]) >= particles)
      fail("element " + std::to_string(e) + " stands for particle " + std::to_string(c.particle[e]));
    seen.assign(c.corner_vertex.begin() + c.corner_start[e], c.corner_vertex.begin() + c.corner_start[e + 1]);
    std::sort(seen.begin(), seen.end());
    if (std::adjacent_find(seen.begin(), seen.end()) != seen.end())
      fail("element " + std::to_string(e) + " lists a vertex twice");
    for (int32_t v : seen)
      if (v < 0 || size_t(v) >= c.vertices.size())
        fail("element " + std::to_string(e) + " has vertex " + std::to_string(v));
    for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f) {
      const int64_t b = c.face_corner_start[size_t(f)], end = c.face_corner_start[size_t(f) + 1];
      if (end - b < 3) fail("face " + std::to_string(f) + " has fewer than 3 corners");
      for (int64_t k = b; k < end; ++k)
        if (c.face_corner[size_t(k)] < c.corner_start[e] || c.face_corner[size_t(k)] >= c.corner_start[e + 1])
          fail("face " + std::to_string(f) + " uses a corner of another element");
      const int32_t o = c.face_other[size_t(f)];
      if (o < -1 || o >= int32_t(particles))
        fail("face " + std::to_string(f) + " borders particle " + std::to_string(o));
    }
  }
}

double element_volume(const ElementComplex& c, size_t e) {
  double six_v = 0;
  const Vec3d& o = c.vertices[size_t(c.corner_vertex[size_t(c.corner_start[e])])];
  auto at = [&](int64_t k) {
    return c.vertices[size_t(c.corner_vertex[size_t(c.face_corner[size_t(k)])])] - o;
  };
  for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f) {
    const int64_t b = c.face_corner_start[size_t(f)], end = c.face_corner_start[size_t(f) + 1];
    for (int64_t k = b + 1; k + 1 < end; ++k) six_v += dot(at(b), cross(at(k), at(k + 1)));
  }
  return six_v / 6;
}

}  // namespace pd
