// Regular-grid particles: each particle is a cube of side `spacing` (Levine sec. 4).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cuda/vec3.h"

namespace pd {

// Particles per axis for a box: round(size / spacing), at least 1.
std::array<int64_t, 3> box_grid_counts(const std::array<double, 3>& size, double spacing);

// Centres of the cubes filling a box of `size` centred at `center`, x fastest, then y, z.
std::vector<Vec3> box_grid_points(const std::array<double, 3>& center, const std::array<double, 3>& size,
                                  double spacing);

}  // namespace pd
