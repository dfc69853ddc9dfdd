// Rest-space surfaces of the fragments, for artists who re-render pieces in their own tools: a
// fragment's surface is every face of its elements (cubes, tets, Voronoi cells cut to the object;
// element_complex.h) that borders an element of another fragment or nothing. Moved by the
// per-frame transforms of the fragments file, the pieces follow the simulation.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/fragments/components.h"
#include "host/fragments/element_complex.h"
#include "host/geometry/vec3d.h"

namespace pd {

// Surfaces as one object per fragment, in component order. Vertices are the complex's, one per
// object, so each object's surface is closed and pieces on both sides of a crack meet exactly.
struct FragmentMesh {
  std::vector<Vec3d> vertices;            // rest space [m]
  std::vector<int64_t> polygon_start{0};  // polygon q: polygon_vertex[polygon_start[q] .. [q + 1])
  std::vector<int32_t> polygon_vertex;    // vertex indices, counter-clockwise seen from outside
  std::vector<int32_t> ids;               // fragment id of each object
  std::vector<int64_t> vertex_start{0};   // object o: vertices [vertex_start[o], vertex_start[o + 1])
  std::vector<int64_t> object_start{0};   // object o: polygons [object_start[o], object_start[o + 1])

  size_t objects() const { return ids.size(); }
  size_t polygons() const { return polygon_start.size() - 1; }
};

// The fragments `c` of the particles whose elements are `complex` (element p = particle p, as
// assemble() makes it). Throws std::invalid_argument when the sizes differ.
FragmentMesh fragment_pieces(const ElementComplex& complex, const Components& c);

// Writes `mesh` atomically as Wavefront OBJ: one `o fragment_<id>` per object, its `v` lines and
// polygon `f` lines (1-based indices into all vertices of the file). Throws IoError when the file
// cannot be written.
void write_obj(const std::string& path, const FragmentMesh& mesh);

}  // namespace pd
