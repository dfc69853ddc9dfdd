// Rest-space surfaces of the fragments of grid bodies, for artists who re-render pieces in their
// own tools: each particle is a cube of side spacing[i] around its rest position, and a fragment's
// surface is every face between one of its cubes and a cube of another fragment or empty space.
// Moved by the per-frame transforms of the fragments file, the pieces follow the simulation.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "adjacency.h"
#include "components.h"

namespace pd {

// Surfaces as one object per fragment, in component order. Corners shared by cubes are one
// vertex per object, placed at the mean of the cubes' corners, so each object's surface is closed
// and pieces on both sides of a crack meet exactly in rest space.
struct FragmentMesh {
  std::vector<Eigen::Vector3d> vertices;      // rest space [m]
  std::vector<std::array<int32_t, 4>> quads;  // vertex indices, counter-clockwise seen from outside
  std::vector<int32_t> ids;                   // fragment id of each object
  std::vector<int64_t> vertex_start{0};       // object o: vertices [vertex_start[o], vertex_start[o + 1])
  std::vector<int64_t> quad_start{0};         // object o: quads [quad_start[o], quad_start[o + 1])

  size_t objects() const { return ids.size(); }
};

// Meshes the fragments `c` of grid particles whose face neighbours are `adjacency` (e.g.
// grid_adjacency). Throws std::invalid_argument when sizes differ or the adjacency does not fit a
// cube grid (two neighbours on one face, or a cycle of faces that does not close).
FragmentMesh cube_fragment_mesh(const ElementAdjacency& adjacency, const std::vector<Vec3>& rest,
                                const std::vector<real>& spacing, const Components& c);

// Writes `mesh` atomically as Wavefront OBJ: one `o fragment_<id>` per object, its `v` lines and
// quad `f` lines (1-based indices into all vertices of the file). Throws IoError when the file
// cannot be written.
void write_obj(const std::string& path, const FragmentMesh& mesh);

}  // namespace pd
