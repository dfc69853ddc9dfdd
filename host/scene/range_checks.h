// Physical range checks of a set-up, before the run writes anything: every speed below the speed
// of light, and every quantity the kernels hold in the build's precision (`real`: float, or double
// with PERIFRAC_DOUBLE) a finite number there: particle masses and volumes positive, kinetic
// energies and material stiffnesses representable. A scene that fails names the key to change, so
// a density of 1e308 or a velocity of 1e30 m/s is refused in one line instead of filling the first
// frame with inf and NaN.
#pragma once

#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

inline constexpr double kSpeedOfLight = 299792458.0;  // [m/s]

// Throws SceneError naming the scene key (bodies[k].velocity, materials.NAME.density, ...).
void check_physical_ranges(const Scene& scene, const SetupResult& setup);

}  // namespace pd
