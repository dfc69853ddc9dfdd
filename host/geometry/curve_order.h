// Particles in space-filling-curve order (issue 27, item 1): the elements a mesh filler makes
// (TetGen's tets, Poisson-disk sites) come in the order their algorithm found them, so a
// particle's partners sit anywhere in memory and the warps of the force kernels gather them from
// all over the device's cache. Sorted along the Morton (Z-order) curve, particles near in space
// are near in index: a warp's 32 particles share most of their partners.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/vec3d.h"

namespace pd {

// The order of `points` along the Morton curve of a grid of cubic cells, 2^21 along the longest
// side of their bounding box: order[k] is the index of the k-th point. Points in one cell keep
// their input order.
std::vector<int32_t> morton_order(const std::vector<Vec3d>& points);

// `values` rearranged so that entry k is the old entry order[k].
template <class T>
std::vector<T> permuted(const std::vector<T>& values, const std::vector<int32_t>& order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (int32_t old : order) out.push_back(values[size_t(old)]);
  return out;
}

}  // namespace pd
