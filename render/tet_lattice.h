// A block of tetrahedra like a mesher's: an nx x ny x nz lattice of cells of side h (bottom at
// y = 0, centred in x and z) whose vertices are jittered by up to `jitter` h along each axis
// (deterministic), each cell cut into Kuhn's 6 tetrahedra around its diagonal, which conform
// across cells. The render benchmark's slab and the tests' solid meshes.
#pragma once

#include <cstdint>

#include "render/primitive_set.h"

namespace pd {

void add_tet_lattice(PrimitiveSet* prims, int64_t nx, int64_t ny, int64_t nz, double h, double jitter);

}  // namespace pd
