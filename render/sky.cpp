#include "render/sky.h"

namespace pd {

Sh9 sky_sh9(const Sky& s) {
  Sh9 L = project_sh9([&](Vec3 w) { return sky_gradient(s, w); });
  real y[9];
  sh9_basis(normalize(s.sun_direction), y);
  for (int k = 0; k < 9; ++k) L.c[k] += y[k] * s.sun_irradiance;
  return L;
}

}  // namespace pd
