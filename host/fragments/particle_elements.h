// The elements of every particle of a scene in one complex (element p = particle p): the clipped
// Voronoi cells of Voronoi bodies, the tets of tet and shell bodies, and a cube of side spacing[p]
// for every other particle (grid bodies).
#pragma once

#include <cstdint>
#include <vector>

#include "cuda/vec3.h"
#include "host/fragments/element_complex.h"
#include "host/fragments/tet_complex.h"
#include "host/fragments/voronoi_complex.h"
#include "host/geometry/element_adjacency.h"
#include "host/geometry/particle_geometry.h"

namespace pd {

// A Voronoi body: its particle geometry (the cells) and the scene index of its first particle.
struct VoronoiElements {
  int32_t first_particle = 0;
  const ParticleGeometry* geometry = nullptr;
};

// `adjacency`: face neighbours over all particles (the cubes' lattice is walked along it).
// `report`, when given, adds up the Voronoi bodies' reports. Throws std::invalid_argument as the
// builders do (cube_complex, tet_complex, voronoi_complex).
ElementComplex particle_elements(const std::vector<Vec3>& rest, const std::vector<real>& spacing,
                                 const ElementAdjacency& adjacency, const EmbeddedTets& tets,
                                 const std::vector<VoronoiElements>& voronoi,
                                 VoronoiComplexReport* report = nullptr);

}  // namespace pd
