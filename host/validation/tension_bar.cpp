// Static tension bar (docs/validation.md, "tension_bar"): elongation F L / (E A) and Poisson's
// ratio. A bar n x n particles across, with a free length of 4 widths between two grips of
// ceil(delta/lambda) layers, is stretched at a constant strain rate: the grips move with
// v_x = rate x (x from the bar's centre) and are held laterally, and every particle starts with
// that velocity, so the quasi-static solution (homogeneous uniaxial stress) holds from the first
// step and no stress wave is launched. What the dynamics adds (breathing of the cross-section,
// waves from the grips' lateral clamping) oscillates about the static answer and is averaged out
// by least-squares fits over the samples of the second half of the run, as in a tensile test:
//   stress sigma = F / A, F the mean of the two grips' reactions, A = (n lambda)^2;
//   axial strain from a gauge section of one width at the centre (slope of u_x against x);
//   lateral strain in the same section (slopes of u_y against y and u_z against z);
//   E = d sigma / d eps_axial, nu = -d eps_lateral / d eps_axial.
// The gauge sits two widths from each grip, where Saint-Venant's end effects of the clamps have
// decayed. Reported: the gauge elongation under the final force against F L_g / (E A), and nu
// against the model's (1/4 for PMB, the input for the state-based solid).
#include <cmath>
#include <utility>
#include <vector>

#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

constexpr double kFreeLengthOverWidth = 4;
constexpr double kFinalStrain = 5e-4;
constexpr double kWidthTransits = 40;  // run length in lateral transit times W / c0
constexpr int kSamples = 40;           // over the second half of the run

std::vector<ValidationResult> tension_bar(const ValidationCase& c, const ElasticSolid& solid,
                                          const char* name) {
  const WallClock clock;
  const int n = c.resolution;
  const double m = c.delta_over_lambda, width = 0.01, lambda = width / n;
  const int grip = int(std::ceil(m)), nx = int(kFreeLengthOverWidth * n) + 2 * grip;
  const double c0 = std::sqrt(solid.youngs / solid.density);
  const double dt = c.dt_fraction * validation_critical_dt(solid, lambda, m);
  const int64_t steps = int64_t(std::ceil(kWidthTransits * width / (c0 * dt)));
  const double rate = kFinalStrain / (double(steps) * dt);

  // The bar, centred on the origin; grips at both ends; gauge = the central width.
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = validation_material(solid, lambda, m, c.surface_correction, c.surface_ghosts);
  in.step.dt = real(dt);
  const double half = 0.5 * nx * lambda;
  const double corner[3] = {-half, -0.5 * width, -0.5 * width};
  std::vector<int> left, right, gauge;
  for_each_cube(nx, n, n, lambda, corner, [&](int i, int, int, double x, double y, double z) {
    const bool is_grip = i < grip || i >= nx - grip;
    const size_t p = add_cube(in.particles, x, y, z, lambda, solid, 1.0, is_grip ? kAnchored : 0);
    in.particles.velocity[p] = {real(rate * x), 0, 0};
    if (i < grip) left.push_back(int(p));
    if (i >= nx - grip) right.push_back(int(p));
    if (std::fabs(x) < 0.5 * width) gauge.push_back(int(p));
  });

  auto engine = make_engine(c.backend, in);
  engine->advance(steps / 2);
  const int64_t chunk = std::max<int64_t>(1, (steps - steps / 2) / kSamples);
  std::vector<double> stress, axial, lateral;
  ParticleState s;
  const auto& rest = in.particles.rest;
  auto slope = [&](int axis) {
    std::vector<double> x, u;
    for (int p : gauge) {
      x.push_back(axis == 0 ? rest[p].x : axis == 1 ? rest[p].y : rest[p].z);
      u.push_back(axis == 0 ? s.disp[p].x : axis == 1 ? s.disp[p].y : s.disp[p].z);
    }
    return fit_slope(x.data(), u.data(), x.size());
  };
  while (engine->step() < steps) {
    engine->advance(chunk);
    engine->read_state(s);
    const double f = grip_force(s, left, right);
    stress.push_back(f / (width * width));
    axial.push_back(slope(0));
    lateral.push_back(0.5 * (slope(1) + slope(2)));
  }
  const double modulus = fit_slope(axial.data(), stress.data(), axial.size());
  const double nu = -fit_slope(axial.data(), lateral.data(), axial.size());

  // Gauge elongation under the final force F: F L_g / (E_measured A) against F L_g / (E A).
  const double force = stress.back() * width * width;
  const double measured = force * width / (modulus * width * width);
  const double reference = force * width / (solid.youngs * width * width);
  std::vector<ValidationResult> out = {make_result(std::string(name) + "/elongation", measured, reference),
                                       make_result(std::string(name) + "/poisson", nu, solid.nu())};
  return stamped(std::move(out), in, *engine, clock, "E_measured " + std::to_string(modulus / 1e9) + " GPa");
}

}  // namespace

std::vector<ValidationResult> run_tension_bar_pmb(const ValidationCase& c) {
  return tension_bar(c, {72e9, 0.25, 2440, false}, "tension_bar_pmb");
}

// A state-based solid with nu = 0.3 (aluminium-like constants).
std::vector<ValidationResult> run_tension_bar_lps(const ValidationCase& c) {
  return tension_bar(c, {70e9, 0.3, 2700, true}, "tension_bar_lps");
}

}  // namespace pd
