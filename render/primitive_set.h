// Host-side owner of a primitive scene: the arrays behind a PrimitivesView.
#pragma once

#include <vector>

#include "primitives.h"

namespace pd {

struct PrimitiveSet {
  std::vector<uint8_t> kind;
  std::vector<int32_t> slot;
  std::vector<Vec3> cube_center;
  std::vector<real> cube_half;
  std::vector<Vec3> tet_vertex;

  int32_t size() const { return int32_t(kind.size()); }

  // Both return the new primitive's index.
  int32_t add_cube(Vec3 center, real half) {
    kind.push_back(kPrimCube);
    slot.push_back(int32_t(cube_center.size()));
    cube_center.push_back(center);
    cube_half.push_back(half);
    return size() - 1;
  }
  int32_t add_tet(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    kind.push_back(kPrimTet);
    slot.push_back(int32_t(tet_vertex.size() / 4));
    tet_vertex.insert(tet_vertex.end(), {a, b, c, d});
    return size() - 1;
  }

  // A view of the host arrays (host-side tests and the kd-tree build).
  PrimitivesView view() const {
    return {size(), kind.data(), slot.data(), cube_center.data(), cube_half.data(), tet_vertex.data()};
  }

  std::vector<Box> bounds() const {
    std::vector<Box> b(kind.size());
    const PrimitivesView v = view();
    for (int32_t i = 0; i < size(); ++i) b[i] = primitive_bounds(v, i);
    return b;
  }
};

}  // namespace pd
