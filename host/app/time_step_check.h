// Whether a run's time step is stable: the continuum estimate from the materials (before the
// families exist) and the one from the particles' families (after), or with ghost-corrected
// materials the step measured on the engine. `perifrac run` and `perifrac bench` refuse a dt past
// either unless allowed, naming the scene key that sets it.
#pragma once

#include <optional>

#include "cuda/engine/engine.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

// Throws SceneError (simulation.dt) when dt exceeds the continuum estimate and `allow` is off.
void check_time_step(const Scene& scene, const SetupResult& setup, bool allow);

// The stable step measured on an engine with ghost-corrected materials (cuda/engine/stable_step.h):
// the families' estimate cannot follow the ghosts' reach.
struct MeasuredStep {
  double stable = 0;   // [s], rounded down to 8 significant bits (rounded_down_step)
  int passes = 0;      // force passes taken
  double seconds = 0;  // wall time of the measurement
};

// Runs whose materials have ghosts: the step measured on `engine` (built from `in`), and with
// `dt_auto` a new dt, kAutoDtFraction of the measured step or of the continuum `critical_dt`
// where that is shorter, set on the engine and in `dt`. Other runs: nothing measured or changed.
std::optional<MeasuredStep> measure_ghost_step(Engine& engine, const SimulationInput& in, bool dt_auto,
                                               double critical_dt, double& dt);

// dt = "auto" without ghosts: kAutoDtFraction of the continuum estimate, or the families' stable
// step `family_dt` where that is shorter (a body thinner than its horizon somewhere): the families'
// estimate is itself about half the step Verlet stands (bench/NOTES.md), so "auto" stays half the
// stable step and never takes one the check below refuses. Sets it on `engine` and in `dt`;
// returns whether dt was lowered.
bool auto_step_within_families(Engine& engine, bool dt_auto, double family_dt, double& dt);

// Throws SceneError (simulation.dt) when dt exceeds `family_dt` (Engine::critical_time_step, or
// with ghosts the step measured on the engine: `measured`) and `allow` is off.
void check_family_time_step(const Scene& scene, double dt, double family_dt, bool allow,
                            bool measured = false);

}  // namespace pd
