// Whether a run's time step is stable: the continuum estimate from the materials (before the
// families exist) and the one from the particles' families (after). `perifrac run` and
// `perifrac bench` refuse a dt past either unless allowed, naming the scene key that sets it.
#pragma once

#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

// Throws SceneError (simulation.dt) when dt exceeds the continuum estimate and `allow` is off.
void check_time_step(const Scene& scene, const SetupResult& setup, bool allow);

// Throws SceneError (simulation.dt) when dt exceeds `family_dt` (Engine::critical_time_step)
// and `allow` is off.
void check_family_time_step(const Scene& scene, double dt, double family_dt, bool allow);

}  // namespace pd
