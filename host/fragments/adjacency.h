// Element adjacency: which particles' geometric elements touch (cube faces, tet faces, Voronoi
// facets). It is the graph whose unbroken part splits a body into fragments (Levine sec. 4), a
// subset of the family bonds. Grid bodies derive it here; meshed bodies get it from their geometry.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "../engine.h"
#include "../particle_set.h"

namespace pd {

// Symmetric neighbour lists in CSR form: the elements adjacent to particle i are
// neighbor[offset[i] .. offset[i + 1]); j is listed for i exactly when i is listed for j.
struct ElementAdjacency {
  std::vector<int64_t> offset{0};  // particles + 1 entries
  std::vector<int32_t> neighbor;

  size_t size() const { return offset.size() - 1; }
};

// Adjacency of `n` particles from undirected pairs (each pair once, either order). Throws
// std::invalid_argument for an index outside [0, n), a self pair or a repeated pair.
ElementAdjacency adjacency_from_pairs(size_t n, const std::vector<std::pair<int32_t, int32_t>>& pairs);

// Cube side of each grid particle: the spacing lambda of its material.
std::vector<real> particle_spacing(const ParticleSet& particles, const MaterialTable& materials);

// Face neighbours of grid particles (cubes of side spacing[i]): the family bonds whose rest length
// is within 1% of the cube side of both ends. Families list each bond from both ends, so the
// result is symmetric; broken bonds count too (adjacency is a rest-state property).
ElementAdjacency grid_adjacency(const BondLists& bonds, const std::vector<Vec3>& rest,
                                const std::vector<real>& spacing);

}  // namespace pd
