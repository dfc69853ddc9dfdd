// The solids of tet bodies for the ghost surface correction (cuda/engine/body_solids.h): each
// body's tet mesh, its tets' faces without a neighbour as a closed surface, tested by the
// inside test (inside_test.h), one ray per line of stencil points.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "cuda/engine/body_solids.h"
#include "host/geometry/inside_test.h"
#include "host/geometry/tet_mesh.h"

namespace pd {

// The closed surface of a tet mesh: the faces opposite the corners without a neighbour.
TriMesh tet_boundary(const TetMesh& mesh);

class TetBodySolids final : public BodySolids {
 public:
  // Body `body`'s solid: the union of `mesh`'s tets (in the particles' frame).
  void add(int32_t body, const TetMesh& mesh);
  bool empty() const { return solids_.empty(); }

  bool has(int32_t body) const override;
  void inside_along_x(int32_t body, double x0, double dx, double y, double z, int count,
                      uint8_t* inside) const override;

 private:
  struct Solid {
    TriMesh surface;
    InsideTest test;
    explicit Solid(TriMesh s) : surface(std::move(s)), test(surface) {}
  };
  std::vector<std::unique_ptr<const Solid>> solids_;  // by body; null where a body has none
};

}  // namespace pd
