// Tetrahedra that no ray from outside can reach first. A face of an opaque tetrahedron is
// covered when it is also a face of another opaque tetrahedron on its other side (the same three
// vertices, bit for bit); the uncovered faces are the solid's skin. A tetrahedron with four
// covered faces lies inside the union of its neighbours: every point of its boundary belongs to
// one of them, so a ray from outside meets a neighbour at the same t or before. Such a
// tetrahedron is hidden when, moreover, none of its vertices lies on the skin: then every
// tetrahedron that touches the skin stays, and a ray that crosses the skin within round-off of
// an edge or a vertex still runs into one of them over a finite stretch (their shared faces
// give the same crossing in both, tet_face), where a one-tetrahedron shell would let it slip
// through the tetrahedra it only grazes. Leaving the hidden ones out of the kd-tree drops the
// interior of a solid mesh from the traversal. Faces match only where the two tetrahedra were
// placed by the same transform (one fragment, or a body at rest), so a crack that has opened
// exposes its faces again. Glass is never hidden: rays travel inside it (union_walk.h).
#pragma once

#include <cstdint>
#include <vector>

#include "render/primitive_set.h"

namespace pd {

// The renderer's rule: a hidden tetrahedron has at most this many vertices on the skin. (2 or 4
// give the thinner shells the tests show to leak.)
constexpr int kHiddenMaxSkinVertices = 1;

// One flag per primitive: 1 for a hidden tetrahedron. `material` is empty (all opaque) or one
// SurfaceMaterial per primitive.
std::vector<uint8_t> find_hidden_tets(const PrimitiveSet& prims, const std::vector<uint8_t>& material,
                                      int max_skin_vertices = kHiddenMaxSkinVertices);

}  // namespace pd
