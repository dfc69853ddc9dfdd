// Blue-noise (Poisson-disk) points inside a solid: no two closer than `min_distance`, and
// (nearly) maximal, so no point of the solid is farther than about 2 min_distance from one.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/inside_test.h"

namespace pd {

// Bridson's algorithm (SIGGRAPH 2007 sketch, "Fast Poisson disk sampling in arbitrary
// dimensions"): from each active point, up to 30 random candidates in the shell [r, 2r]; a
// candidate is kept when inside and at least r from every point. It is seeded from every cell of
// its background grid (side r / sqrt 3) whose centre is inside and at least r from every point,
// so every connected part of the solid is filled. Parallel over tiles of 16^3 background cells
// in eight rounds (tiles of one round are a tile apart, so they never see each other's points),
// each tile with its own random stream: deterministic for a given seed, whatever the number of
// threads. The points come tile by tile.
std::vector<Vec3d> poisson_disk_points(const TriMesh& solid, const InsideTest& inside, double min_distance,
                                       uint64_t seed);

}  // namespace pd
