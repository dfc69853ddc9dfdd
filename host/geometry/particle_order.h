// Rearranging a mesh-filled body's particles, which sets the order the force kernels' threads take
// them in: tets come in space-filling-curve order (curve_order.h; Voronoi sites are sorted before
// their cells are cut). Ordering each run of particles along the curve by family size as well, so
// a warp's 32 threads loop over families of about one size, was measured and not kept
// (bench/NOTES.md: slices 91-97% full instead of 78%, the step within noise).
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/particle_geometry.h"

namespace pd {

// The tet particles of `g` rearranged so that particle k is the old particle order[k]: positions,
// volumes, masses, nearest distances, the adjacency (where it has been built) and the tets with
// their neighbours follow.
void reorder_particles(ParticleGeometry& g, const std::vector<int32_t>& order);

}  // namespace pd
