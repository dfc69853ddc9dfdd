// Element adjacency: which particles' geometric elements touch (cube faces, tet faces, Voronoi
// facets). It is the graph whose unbroken part splits a body into fragments (Levine sec. 4), a
// subset of the family bonds. Grid bodies derive it here; meshed bodies get it from their geometry.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/engine/particle_set.h"
#include "host/geometry/element_adjacency.h"

namespace pd {

// Cube side of each grid particle: the spacing lambda of its material.
std::vector<real> particle_spacing(const ParticleSet& particles, const MaterialTable& materials);

// Face neighbours of grid particles (cubes of side spacing[i]): the family bonds whose rest length
// is within 1% of the cube side of both ends. Families list each bond from both ends, so the
// result is symmetric; broken bonds count too (adjacency is a rest-state property).
ElementAdjacency grid_adjacency(const BondLists& bonds, const std::vector<Vec3>& rest,
                                const std::vector<real>& spacing);

}  // namespace pd
