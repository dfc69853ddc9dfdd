// The elements of grid particles (Levine sec. 4): each particle is a cube of side spacing[p]
// around its rest position, its six faces bordering the face neighbours of the element adjacency.
// Corners shared by cubes are one vertex, placed at the mean of the cubes' own corners, so pieces
// cut from the complex are closed and meet exactly across a crack in rest space.
#pragma once

#include <cstdint>
#include <vector>

#include "cuda/vec3.h"
#include "host/fragments/element_complex.h"
#include "host/geometry/element_adjacency.h"

namespace pd {

// The cubes of the particles `cubes` (indices into the per-particle arrays; their neighbours in
// `adjacency`, e.g. grid_adjacency, must be cubes of the list too). Element k stands for particle
// cubes[k]; its corners are the 8 cube corners (bit 0: +x, 1: +y, 2: +z) and its faces the 6 quads.
// Throws std::invalid_argument when sizes differ or the adjacency does not fit a cube grid (two
// neighbours across one face, a cycle of faces that does not close, a neighbour not in `cubes`).
ElementComplex cube_complex(const ElementAdjacency& adjacency, const std::vector<Vec3>& rest,
                            const std::vector<real>& spacing, const std::vector<int32_t>& cubes);

}  // namespace pd
