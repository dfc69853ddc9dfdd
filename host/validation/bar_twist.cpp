// Twisted bar (docs/validation.md, "bar_twist"): Saint-Venant torsion of a square bar, the
// small-strain counterpart of Chen et al.'s twisting bar (Fig. 12). A bar n x n particles across
// (side a), with a free length of 4 a between two grips of ceil(delta/lambda) layers, is twisted
// at a constant rate: the left grip is held, the right grip turns about the bar's axis (x) at
// angular velocity w, and every particle starts with the velocity of the linear twist field,
// w (x - x_left) / L_grips about the axis, so the quasi-static solution holds from the first step
// (the square section's warping is not set up front: it oscillates about its static shape and is
// averaged out). The grips move linearly along their initial tangents; at the final angle of
// 5e-3 rad this differs from a rotation by 1e-5 of a radius, far below what is measured.
// Measured as in a torsion test:
//   torque T = the mean of the two grips' reaction moments about the axis;
//   twist per length theta' = the least-squares slope of the section rotation phi(x) over a gauge
//   section of one side a at the centre (phi of a particle = (y u_z - z u_y) / (y^2 + z^2));
//   torsional stiffness G J = dT / d theta' (least-squares over 40 samples of the second half).
// Reference: J = k a^4 with k = 0.1406 for a square (Timoshenko & Goodier, Theory of Elasticity,
// sec. 109: k1 = 0.141 at b/a = 1; the series gives 0.14058). Reported: the gauge twist angle
// under the final torque, T a / (G J_measured), against T a / (G k a^4).
#include <cmath>
#include <vector>

#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

constexpr double kFreeLengthOverSide = 4;
constexpr double kFinalSurfaceShear = 5e-4;  // theta' a / 2 at the end of the run
constexpr double kSideTransits = 40;         // run length in shear-wave transits of the side
constexpr int kSamples = 40;                 // over the second half of the run
constexpr double kSquareTorsionConstant = 0.14058;

std::vector<ValidationResult> bar_twist(const ValidationCase& c, const ElasticSolid& solid,
                                        const char* name) {
  const WallClock clock;
  const int n = c.resolution;
  const double m = c.delta_over_lambda, side = 0.01, lambda = side / n;
  const int grip = int(std::ceil(m)), nx = int(kFreeLengthOverSide * n) + 2 * grip;
  const double shear_speed = std::sqrt(solid.shear() / solid.density);
  const double dt = c.dt_fraction * validation_critical_dt(solid, lambda, m);
  const int64_t steps = int64_t(std::ceil(kSideTransits * side / (shear_speed * dt)));

  // Twist rate of the right grip relative to the left one (their centres are `span` apart).
  const double half = 0.5 * nx * lambda, span = (nx - grip) * lambda;
  const double final_twist_rate = 2 * kFinalSurfaceShear / side;  // theta' [rad/m]
  const double spin = final_twist_rate * span / (double(steps) * dt);

  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = validation_material(solid, lambda, m, c.surface_correction, c.surface_ghosts);
  in.step.dt = real(dt);
  const double corner[3] = {-half, -0.5 * side, -0.5 * side};
  std::vector<int> left, right, gauge;
  const double x_left = -half + 0.5 * grip * lambda;  // the left grip's centre
  for_each_cube(nx, n, n, lambda, corner, [&](int i, int, int, double x, double y, double z) {
    const bool is_grip = i < grip || i >= nx - grip;
    const size_t p = add_cube(in.particles, x, y, z, lambda, solid, 1.0, is_grip ? kAnchored : 0);
    const double w = i < grip ? 0 : i >= nx - grip ? spin : spin * (x - x_left) / span;
    in.particles.velocity[p] = {0, real(-w * z), real(w * y)};
    if (i < grip) left.push_back(int(p));
    if (i >= nx - grip) right.push_back(int(p));
    if (std::fabs(x) < 0.5 * side) gauge.push_back(int(p));
  });

  std::string stable_note;
  auto engine = validation_engine(c, in, stable_note);
  engine->advance(steps / 2);
  const int64_t chunk = std::max<int64_t>(1, (steps - steps / 2) / kSamples);
  const auto& rest = in.particles.rest;
  ParticleState s;
  auto moment = [&](const std::vector<int>& grip_particles) {
    double t = 0;
    for (int p : grip_particles) t += rest[p].y * s.force[p].z - rest[p].z * s.force[p].y;
    return t;
  };
  // Twist per length in the gauge: the least-squares slope of the particles' rotation angle about
  // the axis against x (warping moves particles along x only and leaves the angle alone).
  auto twist_rate = [&]() {
    std::vector<double> x, phi;
    for (int p : gauge) {
      const double y = rest[p].y, z = rest[p].z, r2 = y * y + z * z;
      x.push_back(rest[p].x);
      phi.push_back((y * s.disp[p].z - z * s.disp[p].y) / r2);
    }
    return fit_slope(x.data(), phi.data(), x.size());
  };
  std::vector<double> torque, twist;
  while (engine->step() < steps) {
    engine->advance(chunk);
    engine->read_state(s);
    torque.push_back(0.5 * (moment(left) - moment(right)));
    twist.push_back(twist_rate());
  }
  const double stiffness = fit_slope(twist.data(), torque.data(), twist.size());  // G J

  const double reference_stiffness = solid.shear() * kSquareTorsionConstant * std::pow(side, 4);
  const double final_torque = torque.back();
  ValidationResult r = make_result(std::string(name) + "/twist_angle", final_torque * side / stiffness,
                                   final_torque * side / reference_stiffness);
  return stamped({r}, in, *engine, clock,
                 "GJ_measured/GJ " + std::to_string(stiffness / reference_stiffness) + stable_note);
}

}  // namespace

std::vector<ValidationResult> run_bar_twist_lps(const ValidationCase& c) {
  return bar_twist(c, {70e9, 0.3, 2700, true}, "bar_twist_lps");
}

}  // namespace pd
