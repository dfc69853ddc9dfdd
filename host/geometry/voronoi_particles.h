// Voronoi particles (Levine sec. 4 "Voronoi-based geometry"): Poisson-disk sites inside a
// solid, each owning its Voronoi cell cut to the solid, with the surface triangles that cross
// the cell (the trimtope) kept for the renderer. Cells sharing a face inside the solid are
// adjacent. Own half-space clipping (no Voronoi library): each cell starts as the cube of
// half-side 2r around its site — every point of the solid nearer to that site than to any other
// lies within 2r of it, since Poisson-disk sampling leaves no wider gap — and is cut by the
// bisector planes of the sites within 4r, nearest first, until no farther site can cut it.
#pragma once

#include <cstdint>
#include <string>

#include "host/geometry/particle_geometry.h"

namespace pd {

// Volumes are exact for the polyhedral solid: V(cell ∩ solid) by the divergence theorem over
// the clipped surface triangles and the parts of the cell's faces inside the solid (those by
// the same theorem in the face's plane, down to the inside intervals of the cell's edges).
// `min_distance` is r. MeshError naming `name` when the solid would need more than max_particles
// sites (estimated at 0.7 per r^3, the density of maximal Poisson-disk samples). The sites come
// in space-filling-curve order (curve_order.h).
ParticleGeometry voronoi_particles(const TriMesh& solid, double min_distance, uint64_t seed,
                                   int64_t max_particles, const std::string& name);

}  // namespace pd
