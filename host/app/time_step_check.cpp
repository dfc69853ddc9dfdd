#include "host/app/time_step_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "cuda/engine/stable_step.h"

namespace pd {

namespace {
constexpr const char* kWaysOut =
    "; give a smaller simulation.dt, or --set 'simulation.dt=\"auto\"' (half the stable step), or pass "
    "--allow-unstable-dt to run anyway";
}  // namespace

std::optional<MeasuredStep> measure_ghost_step(Engine& engine, const SimulationInput& in, bool dt_auto,
                                               double critical_dt, double& dt) {
  const MaterialTable& mt = in.materials;
  if (std::none_of(mt.m, mt.m + mt.count, [](const Material& m) { return m.ghost_correction != 0; }))
    return std::nullopt;
  const auto t0 = std::chrono::steady_clock::now();
  const StableStep measured = measure_stable_step(engine, in);
  MeasuredStep out;
  out.stable = rounded_down_step(measured.seconds);
  out.passes = measured.iterations + 1;  // and the baseline's
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (dt_auto) {
    dt = kAutoDtFraction * std::fmin(critical_dt, out.stable);
    engine.set_time_step(dt);
  }
  return out;
}

bool auto_step_within_families(Engine& engine, bool dt_auto, double family_dt, double& dt) {
  if (!dt_auto || dt <= family_dt) return false;
  dt = family_dt;
  engine.set_time_step(dt);
  return true;
}

void check_time_step(const Scene& scene, const SetupResult& setup, bool allow) {
  if (setup.dt <= setup.critical_dt || allow) return;
  // The material that sets the limit, named with what sets its stable step.
  const MaterialSummary* stiffest = &setup.materials.front();
  for (const MaterialSummary& m : setup.materials)
    if (m.critical_dt < stiffest->critical_dt) stiffest = &m;
  std::ostringstream msg;
  msg << "dt = " << setup.dt << " s exceeds the stable time step " << setup.critical_dt
      << " s of the stiffest material ('" << stiffest->name << "', from its density and moduli: materials."
      << stiffest->name << ")"
      << (scene.colliders.empty() ? "" : " with the colliders' push (colliders' stiffness)")
      << " (allowed: dt <= " << setup.critical_dt << kWaysOut << ")";
  throw SceneError(scene.path, "simulation.dt", msg.str());
}

void check_family_time_step(const Scene& scene, double dt, double family_dt, bool allow, bool measured) {
  if (dt <= family_dt || allow) return;
  std::ostringstream msg;
  msg << "dt = " << dt << " s exceeds the stable time step " << family_dt
      << (measured ? " s measured on the engine with the ghost correction"
                   : " s computed from the particles' families")
      << " (allowed: dt <= " << family_dt << kWaysOut << ")";
  throw SceneError(scene.path, "simulation.dt", msg.str());
}

}  // namespace pd
