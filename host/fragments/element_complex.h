// The rest-space solids the particles stand for (Levine sec. 4), as one polygon complex: a cube, a
// tetrahedron or a Voronoi cell cut to the object per particle, its faces polygons over shared
// vertices, each face knowing the element on its other side. Rest-space piece meshes
// (piece_mesh.h) and Chen's split crack mesh (embedded_mesh.h) are both drawn from it.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/vec3d.h"

namespace pd {

struct ElementComplex {
  std::vector<Vec3d> vertices;  // rest positions [m]
  // Element e stands for particle particle[e]. Its corners are corner_start[e] .. corner_start[e + 1],
  // each a vertex (every vertex of the element once), and its faces face_start[e] .. face_start[e + 1].
  std::vector<int32_t> particle;
  std::vector<int64_t> corner_start{0};
  std::vector<int32_t> corner_vertex;
  std::vector<int64_t> face_start{0};
  // Face f: the corners face_corner[face_corner_start[f] .. face_corner_start[f + 1]) of its element
  // (at least 3, counter-clockwise seen from outside the element), and the particle on its other
  // side, or -1 where the face lies on the object's surface.
  std::vector<int64_t> face_corner_start{0};
  std::vector<int32_t> face_corner;
  std::vector<int32_t> face_other;

  size_t size() const { return particle.size(); }
  size_t faces() const { return face_other.size(); }
  int32_t corners(size_t e) const { return int32_t(corner_start[e + 1] - corner_start[e]); }
  // Starts element e = size() for `p`; then add_corner and add_face fill it.
  void begin_element(int32_t p);
  // Adds a corner at vertex v to the last element; returns its corner index.
  int32_t add_corner(int32_t v);
  // Adds a face of the last element from its corner indices.
  void add_face(const int32_t* corners, size_t count, int32_t other);
};

// The elements of `parts` (each covering some particles, vertices numbered per part) as one
// complex whose element p stands for particle p, p = 0 .. particles - 1. Throws
// std::invalid_argument when a particle has no element or more than one.
ElementComplex assemble(size_t particles, std::vector<ElementComplex> parts);

// Checks the structure: indices in range, faces of at least 3 corners, each element's corners
// distinct vertices, `other` a particle or -1. Throws std::invalid_argument saying what is wrong.
void check(const ElementComplex& c, size_t particles);

// Signed volume of element e by the divergence theorem over its faces (fans of triangles):
// positive when its faces point outwards [m^3].
double element_volume(const ElementComplex& c, size_t e);

}  // namespace pd
