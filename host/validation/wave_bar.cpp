// Longitudinal wave in a bar (docs/validation.md, "wave_bar"). A PMB glass bar, n x n particles
// across and 20 widths long, is pushed at one end by a grip moving at constant speed v0: a step
// in particle velocity runs down the bar. Dispersion (Pochhammer's lateral inertia at wavelengths
// near the width, and the peridynamic dispersion at wavelengths near delta) spreads the step into
// an Airy-function head whose value at x = c0 t is one third of the step (Skalak 1957; Graff,
// Wave Motion in Elastic Solids, sec. 8.2.1), c0 = sqrt(E/rho) the bar velocity. The front is
// tracked at that one-third level, and its speed is the slope of a line fitted to its positions.
#include <algorithm>
#include <cmath>
#include <vector>

#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

constexpr double kLengthOverWidth = 20;
constexpr double kGripSpeed = 1.0;  // v0 [m/s]: strain v0 / c0 ~ 2e-4

// Position of the front: the last cross-section layer (counted from the far end) whose mean
// velocity reaches v0/3, interpolated linearly with the layer ahead of it.
double front_position(const std::vector<double>& layer_speed, double lambda) {
  const double level = kGripSpeed / 3;
  for (size_t i = layer_speed.size() - 1; i > 0; --i)
    if (layer_speed[i - 1] >= level && layer_speed[i] < level) {
      const double f = (layer_speed[i - 1] - level) / (layer_speed[i - 1] - layer_speed[i]);
      return (double(i - 1) + 0.5 + f) * lambda;
    }
  return 0;
}

}  // namespace

std::vector<ValidationResult> run_wave_bar(const ValidationCase& c) {
  const WallClock clock;
  const ElasticSolid& glass = kGlass;
  const int n = c.resolution, nx = int(kLengthOverWidth * n);
  const double width = 0.01, lambda = width / n, m = c.delta_over_lambda;
  const int grip_layers = int(std::ceil(m));

  // The bar along x; the first `grip_layers` layers are the grip.
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = validation_material(glass, lambda, m, c.surface_correction, c.surface_ghosts);
  const double corner[3] = {0, 0, 0};
  for_each_cube(nx, n, n, lambda, corner, [&](int i, int, int, double x, double y, double z) {
    const bool grip = i < grip_layers;
    const size_t p = add_cube(in.particles, x, y, z, lambda, glass, 1.0, grip ? kAnchored : 0);
    if (grip) in.particles.velocity[p] = {real(kGripSpeed), 0, 0};
  });
  const double dt = c.dt_fraction * validation_critical_dt(glass, lambda, m);
  in.step.dt = real(dt);

  // Front positions while the front runs from 3 to 17 widths (clear of the grip's start-up and
  // of the far end's reflection), sampled about every lambda / 2 of travel.
  const double c0 = std::sqrt(glass.youngs / glass.density);
  std::string stable_note;
  auto engine = validation_engine(c, in, stable_note);
  const int64_t chunk = std::max<int64_t>(1, int64_t(0.5 * lambda / (c0 * dt)));
  std::vector<double> times, fronts, layer(static_cast<size_t>(nx));
  ParticleState s;
  while (true) {
    engine->advance(chunk);
    engine->read_state(s);
    std::fill(layer.begin(), layer.end(), 0.0);
    for (size_t p = 0; p < s.vel.size(); ++p) layer[p % size_t(nx)] += double(s.vel[p].x) / (n * n);
    const double x = front_position(layer, lambda);
    if (x > 17 * width || engine->step() * dt * c0 > 1.5 * kLengthOverWidth * width) break;
    if (x >= 3 * width) times.push_back(engine->time()), fronts.push_back(x);
  }
  const double speed = fit_slope(times.data(), fronts.data(), times.size());

  ValidationResult r = make_result("wave_bar/front_speed", speed, c0);
  return stamped({r}, in, *engine, clock, std::to_string(times.size()) + " front samples" + stable_note);
}

}  // namespace pd
