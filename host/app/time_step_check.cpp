#include "host/app/time_step_check.h"

#include <sstream>

namespace pd {

namespace {
constexpr const char* kWaysOut =
    "; give a smaller simulation.dt, or --set 'simulation.dt=\"auto\"' (half the stable step), or pass "
    "--allow-unstable-dt to run anyway";
}  // namespace

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

void check_family_time_step(const Scene& scene, double dt, double family_dt, bool allow) {
  if (dt <= family_dt || allow) return;
  std::ostringstream msg;
  msg << "dt = " << dt << " s exceeds the stable time step " << family_dt
      << " s computed from the particles' families (allowed: dt <= " << family_dt << kWaysOut << ")";
  throw SceneError(scene.path, "simulation.dt", msg.str());
}

}  // namespace pd
