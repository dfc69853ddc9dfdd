// Cantilever under its own weight (docs/validation.md, "cantilever"). A square beam, n x n
// particles across (height h) and L = 5 h long, is clamped at x < 0 by ceil(delta/lambda) layers
// of fixed particles and loaded by a uniform body force g (gravity, along -y): a distributed load
// q = rho g A. Timoshenko beam theory (Timoshenko & Gere, Mechanics of Materials; shear
// coefficient of a rectangle kappa = 10 (1 + nu) / (12 + 11 nu), Cowper 1966) gives the
// deflection at distance x from the clamp
//   w(x) = q (x^4 - 4 L x^3 + 6 L^2 x^2) / (24 E I) + q (L x - x^2 / 2) / (kappa G A),
// compared at the centre of the last layer of particles, x = L - lambda/2.
// The load is applied suddenly, so the beam swings about its static deflection. The first
// maximum of the tip deflection comes half a period after the start; the static deflection is
// the mean tip deflection over the full period that follows from it (the fundamental mode
// averages to zero over a period; higher modes nearly so).
#include <algorithm>
#include <cmath>
#include <vector>

#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

constexpr double kLengthOverHeight = 5;
constexpr double kRootStrain = 2e-4;  // bending strain at the clamp, sets g
constexpr int kSamplesPerPeriod = 200;

std::vector<ValidationResult> cantilever(const ValidationCase& c, const ElasticSolid& solid,
                                         const char* name) {
  const WallClock clock;
  const int n = c.resolution, nl = int(kLengthOverHeight * n);
  const double m = c.delta_over_lambda, h = 0.01, lambda = h / n, length = nl * lambda;
  const int clamp = int(std::ceil(m));
  const double dt = c.dt_fraction * validation_critical_dt(solid, lambda, m);

  // Load: root strain 3 rho g L^2 / (E h) from the Euler-Bernoulli root moment q L^2 / 2.
  const double g = kRootStrain * solid.youngs * h / (3 * solid.density * length * length);
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = validation_material(solid, lambda, m, c.surface_correction);
  in.step.dt = real(dt);
  in.step.gravity = {0, real(-g), 0};
  const double corner[3] = {-clamp * lambda, -0.5 * h, -0.5 * h};
  std::vector<int> tip;
  for_each_cube(nl + clamp, n, n, lambda, corner, [&](int i, int, int, double x, double y, double z) {
    const size_t p = add_cube(in.particles, x, y, z, lambda, solid, 1.0, i < clamp ? kAnchored : 0);
    if (i == nl + clamp - 1) tip.push_back(int(p));
  });

  // Timoshenko deflection at the last layer's centres.
  const double area = h * h, inertia = h * h * h * h / 12, q = solid.density * g * area;
  const double kappa = 10 * (1 + solid.nu()) / (12 + 11 * solid.nu()), x = length - 0.5 * lambda;
  const double reference = q * (std::pow(x, 4) - 4 * length * std::pow(x, 3) + 6 * length * length * x * x) /
                               (24 * solid.youngs * inertia) +
                           q * (length * x - 0.5 * x * x) / (kappa * solid.shear() * area);

  // Sample the tip deflection; the run ends one period after the first maximum (the period is
  // 2 t_max); the Euler-Bernoulli period only sets the sampling interval.
  const double omega =
      1.875104 * 1.875104 * std::sqrt(solid.youngs * inertia / (solid.density * area)) / (length * length);
  const int64_t chunk = std::max<int64_t>(1, int64_t(2 * M_PI / omega / dt / kSamplesPerPeriod));
  auto engine = make_engine(c.backend, in);
  ParticleState s;
  std::vector<double> w = {0};
  size_t peak = 0;
  while (peak == 0 || w.size() < 3 * peak + 1) {
    engine->advance(chunk);
    engine->read_state(s);
    double sum = 0;
    for (int p : tip) sum -= s.disp[p].y;
    w.push_back(sum / double(tip.size()));
    // The first maximum: the deflection has fallen well below its largest value so far.
    const size_t top = size_t(std::max_element(w.begin(), w.end()) - w.begin());
    if (peak == 0 && w.back() < 0.5 * w[top]) peak = top;
    if (w.size() > size_t(20 * kSamplesPerPeriod)) break;  // never swung back: reported as is
  }
  // Mean over [t_max, 3 t_max] (trapezoid rule): one full period.
  double mean = 0;
  const size_t end = std::min(w.size() - 1, 3 * peak);
  for (size_t k = peak; k < end; ++k) mean += 0.5 * (w[k] + w[k + 1]) / double(end - peak);

  ValidationResult r = make_result(std::string(name) + "/tip_deflection", mean, reference);
  return stamped({r}, in, *engine, clock,
                 "period " + std::to_string(2 * double(peak) * double(chunk) * dt * 1e3) + " ms");
}

}  // namespace

std::vector<ValidationResult> run_cantilever_pmb(const ValidationCase& c) {
  return cantilever(c, {72e9, 0.25, 2440, false}, "cantilever_pmb");
}

std::vector<ValidationResult> run_cantilever_lps(const ValidationCase& c) {
  return cantilever(c, {70e9, 0.3, 2700, true}, "cantilever_lps");
}

}  // namespace pd
