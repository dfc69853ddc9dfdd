// Edge flips toward a Delaunay surface triangulation, for the procedural surfaces TetGen meshes:
// an edge whose two opposite angles sum to more than pi has a corner inside its diametral sphere,
// which TetGen then splits (bench/NOTES.md: the vase's shell meshed 16% faster with them flipped).
#pragma once

#include "host/geometry/tri_mesh.h"

namespace pd {

// Flips each edge shared by two consistently oriented triangles whose opposite angles (each in
// its triangle's plane) sum to more than pi, where the two triangles' normals are within
// `max_dihedral` radians (a flip moves the surface by about half the bend times a triangle's
// height) and the flipped pair keeps the orientation, in passes over the edges until none
// qualifies (at most 16). Vertices, orientation and the triangle count are kept; an edge whose
// flipped form is already an edge stays. Returns the number of flips.
int64_t delaunay_flips(TriMesh& mesh, double max_dihedral);

}  // namespace pd
