#include "host/scene/range_checks.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace pd {

namespace {

constexpr double kRealMax = double(std::numeric_limits<real>::max());
constexpr double kRealMin = double(std::numeric_limits<real>::min());  // smallest normal
constexpr const char* kPrecision = sizeof(real) == 8 ? "double-precision" : "single-precision";

std::string format(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

double norm(const Vec3d& v) {
  return std::hypot(v[0], v[1], v[2]);  // (no overflow for components up to the double range)
}

// A velocity key at or above the speed of light (or not finite) is refused.
void check_speed(const Scene& scene, const std::string& key, const Vec3d& velocity) {
  const double speed = norm(velocity);
  if (!(speed < kSpeedOfLight))
    throw SceneError(scene.path, key,
                     "a speed of " + format(speed) + " m/s is not below the speed of light (allowed: below " +
                         format(kSpeedOfLight) + " m/s; peridynamics here is Newtonian)");
}

// A keyframed path moving at or above the speed of light between two keyframes is refused.
void check_path_speed(const Scene& scene, const std::string& key, const std::vector<SceneKeyframe>& path) {
  for (size_t k = 1; k < path.size(); ++k) {
    const double dt = path[k][0] - path[k - 1][0];
    const double speed =
        norm({path[k][1] - path[k - 1][1], path[k][2] - path[k - 1][2], path[k][3] - path[k - 1][3]}) / dt;
    if (!(speed < kSpeedOfLight))
      throw SceneError(scene.path, key,
                       "keyframes " + std::to_string(k - 1) + " to " + std::to_string(k) + " move at " +
                           format(speed) + " m/s, not below the speed of light (allowed: below " +
                           format(kSpeedOfLight) + " m/s; peridynamics here is Newtonian)");
  }
}

// Each body's particles: mass and volume positive and finite in `real`, and the kinetic energy
// of the fastest one finite in `real` (the kernels square velocities times masses).
void check_body_particles(const Scene& scene, const SetupResult& setup) {
  const ParticleSet& ps = setup.input.particles;
  for (size_t i = 0; i < ps.size(); ++i) {
    const size_t b = size_t(ps.body[i]);
    const SceneBody& body = scene.bodies[b];
    const std::string& material = setup.materials[b].name;
    const double mass = double(ps.mass[i]), volume = double(ps.volume[i]);
    if (!(volume >= kRealMin && volume <= kRealMax))
      throw SceneError(scene.path, "bodies[" + std::to_string(b) + "].spacing",
                       "body '" + body.name + "' gives particles a volume of " + format(volume) +
                           " m^3, which a " + kPrecision + " build cannot hold (allowed: volumes from " +
                           format(kRealMin) + " to " + format(kRealMax) + " m^3)");
    const double density = find_material(scene, body.material).density;
    if (!(mass >= kRealMin && mass <= kRealMax))
      throw SceneError(scene.path, "materials." + material + ".density",
                       "a density of " + format(density) + " kg/m^3 gives the particles of body '" +
                           body.name + "' a mass of " + format(density * volume) + " kg, which a " +
                           kPrecision + " build cannot hold (allowed: masses from " + format(kRealMin) +
                           " to " + format(kRealMax) + " kg)");
    const Vec3& v = ps.velocity[i];
    const double speed2 = double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z;
    // An anchored particle moves as its anchor says (velocity and spin about the pivot).
    const bool anchored = (ps.flags[i] & kAnchored) != 0;
    const std::string velocity_key = anchored ? "anchors[" + std::to_string(ps.anchor[i]) + "]"
                                              : "bodies[" + std::to_string(b) + "].velocity";
    if (anchored && !(speed2 < kSpeedOfLight * kSpeedOfLight))
      throw SceneError(scene.path, velocity_key,
                       "its velocity and angular_velocity move a particle of body '" + body.name + "' at " +
                           format(std::sqrt(speed2)) + " m/s, not below the speed of light (allowed: below " +
                           format(kSpeedOfLight) + " m/s)");
    if (!(0.5 * mass * speed2 <= kRealMax))
      throw SceneError(scene.path, velocity_key,
                       "a particle of body '" + body.name + "' (mass " + format(mass) + " kg) moving at " +
                           format(std::sqrt(speed2)) + " m/s has a kinetic energy of " +
                           format(0.5 * mass * speed2) + " J, beyond a " + kPrecision +
                           " number (allowed: below " + format(kRealMax) + " J per particle)");
  }
}

// Each material's constants as the kernels hold them, and its stable time step.
void check_materials(const Scene& scene, const SetupResult& setup) {
  for (size_t k = 0; k < setup.materials.size(); ++k) {
    const MaterialSummary& m = setup.materials[k];
    const Material& km = setup.input.materials.m[k];
    const std::string key = "materials." + m.name;
    const SceneMaterial& sm = find_material(scene, m.name);
    for (const double stiffness : {double(km.bulk_modulus), double(km.shear_modulus), m.micromodulus})
      if (!std::isfinite(stiffness) || std::fabs(stiffness) > kRealMax)
        throw SceneError(scene.path, key,
                         "its bulk modulus " + format(sm.bulk_modulus) + " Pa and shear modulus " +
                             format(sm.shear_modulus) + " Pa give stiffnesses beyond a " + kPrecision +
                             " number (allowed: up to " + format(kRealMax) + "): lower the moduli");
    if (sm.fracture_energy && !(real(m.strain_limit) > 0 && m.strain_limit < 1))
      throw SceneError(scene.path, key + ".fracture_energy",
                       "a fracture energy of " + format(*sm.fracture_energy) +
                           " J/m^2 gives a critical stretch of " + format(m.strain_limit) +
                           " at this spacing and horizon (allowed: one giving a stretch in (0, 1): below " +
                           format(*sm.fracture_energy / (m.strain_limit * m.strain_limit)) + " J/m^2 here)");
    if (!(m.critical_dt > 0 && std::isfinite(m.critical_dt)))
      throw SceneError(scene.path, key + ".density",
                       "with a density of " + format(find_material(scene, scene.bodies[k].material).density) +
                           " kg/m^3 its stable time step is " + format(m.critical_dt) +
                           " s: the density and moduli are out of range of each other");
  }
}

}  // namespace

void check_physical_ranges(const Scene& scene, const SetupResult& setup) {
  for (size_t b = 0; b < scene.bodies.size(); ++b)
    check_speed(scene, "bodies[" + std::to_string(b) + "].velocity", scene.bodies[b].velocity);
  for (size_t a = 0; a < scene.anchors.size(); ++a)
    check_speed(scene, "anchors[" + std::to_string(a) + "].velocity", scene.anchors[a].velocity);
  for (size_t p = 0; p < scene.projectiles.size(); ++p)
    check_speed(scene, "projectiles[" + std::to_string(p) + "].velocity", scene.projectiles[p].velocity);
  for (size_t c = 0; c < scene.colliders.size(); ++c)
    check_speed(scene, "colliders[" + std::to_string(c) + "].velocity", scene.colliders[c].velocity);
  for (size_t a = 0; a < scene.anchors.size(); ++a)
    check_path_speed(scene, "anchors[" + std::to_string(a) + "].path", scene.anchors[a].path);
  for (size_t p = 0; p < scene.projectiles.size(); ++p)
    check_path_speed(scene, "projectiles[" + std::to_string(p) + "].path", scene.projectiles[p].path);
  for (size_t c = 0; c < scene.colliders.size(); ++c)
    check_path_speed(scene, "colliders[" + std::to_string(c) + "].path", scene.colliders[c].path);
  // Pushes the kernels hold as `real`: a projectile's strength (eq. 7) and the contact stiffness.
  for (size_t p = 0; p < scene.projectiles.size(); ++p)
    if (!(scene.projectiles[p].strength <= kRealMax))
      throw SceneError(scene.path, "projectiles[" + std::to_string(p) + "].strength",
                       "a strength of " + format(scene.projectiles[p].strength) + " Pa is beyond a " +
                           kPrecision + " number (allowed: up to " + format(kRealMax) + " Pa)");
  if (!(scene.contact_stiffness <= kRealMax))
    throw SceneError(scene.path, "contact.stiffness",
                     "a stiffness of " + format(scene.contact_stiffness) + " Pa is beyond a " + kPrecision +
                         " number (allowed: up to " + format(kRealMax) + " Pa)");
  check_body_particles(scene, setup);
  check_materials(scene, setup);
}

}  // namespace pd
