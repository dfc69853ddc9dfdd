// Where scattered bodies end, for the ghost surface correction (surface_ghosts.h): a stencil
// point of a particle near a surface takes a ghost where it lies outside its body's solid. The
// host gives the test for the bodies whose solid it holds (tets: the tet mesh's boundary); the
// others take the ghost set-up's own rule (a stencil point far from every particle is outside).
#pragma once

#include <cstdint>

namespace pd {

class BodySolids {
 public:
  virtual ~BodySolids() = default;
  // Whether the test knows body `body`'s solid.
  virtual bool has(int32_t body) const = 0;
  // inside[k] = 1 where the point (x0 + k dx, y, z) lies inside body `body`'s solid, else 0, for
  // k in [0, count): one line of points, which a ray-parity test answers with one ray.
  virtual void inside_along_x(int32_t body, double x0, double dx, double y, double z, int count,
                              uint8_t* inside) const = 0;
};

}  // namespace pd
