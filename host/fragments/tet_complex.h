// The elements of tet bodies (Chen sec. 5.2; Levine sec. 4 "mesh-based geometry"): each particle
// stands for one tetrahedron of its body's tet mesh, and tets sharing a face border each other.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "host/fragments/element_complex.h"
#include "host/geometry/tet_mesh.h"
#include "host/geometry/vec3d.h"

namespace pd {

// The tet meshes of all tet bodies of a scene in one: scene-space vertices, tets, and the particle
// each tet stands for (its barycentre). Bodies never share vertices.
struct EmbeddedTets {
  std::vector<Vec3d> vertices;               // rest positions [m]
  std::vector<std::array<int32_t, 4>> tets;  // vertex indices
  std::vector<int32_t> particle;             // per tet: its particle index in the scene

  bool empty() const { return tets.empty(); }
  // Adds one body's mesh whose tet t is particle first_particle + t.
  void append(const TetMesh& mesh, int32_t first_particle);
};

// Element k stands for particle tets.particle[k]: its 4 corners and the 4 triangles opposite them,
// oriented outwards (a negatively oriented tet is turned), bordering the tet across each face.
// Throws std::invalid_argument when a vertex index is out of range, a face is shared by more than
// two tets, or two tets sharing a face stand for the same particle.
ElementComplex tet_complex(const EmbeddedTets& tets);

}  // namespace pd
