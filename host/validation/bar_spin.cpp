// Spinning bar (docs/validation.md, "bar_spin"): large rotation without ghost forces, the check
// behind Chen et al.'s swinging bar (Fig. 11, where linear FEM distorts under rotation and
// peridynamics does not). A free bar n x n particles across (side a) and L = 5 a long starts
// with the velocity field of a rigid rotation about its centre (axis z) at angular velocity w
// and turns one and a half times. A model that is not invariant under rotation builds strain
// from the rotation itself; this one must show only the centrifugal stretch of a spinning rod:
// stress sigma(x) = rho w^2 (L^2/4 - x^2) / 2 along the bar, so the centres of the end layers
// (at x = +-(L - lambda)/2 = +-s) move apart by
//   dL = 2 u(s),  u(x) = rho w^2 (L^2 x / 4 - x^3 / 3) / (2 E).
// Started at rest length, the bar oscillates axially about that stretch (period 2 L / c0, about
// 100 per turn); the stretch is the mean over the last full turn (angles 180 to 540 degrees).
// Also reported: the angular momentum after 1.5 turns against its initial value (pair forces
// along the bonds conserve it exactly, up to round-off).
#include <cmath>
#include <utility>
#include <vector>

#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

constexpr double kLengthOverSide = 5;
constexpr double kPeakStrain = 1e-4;  // centrifugal strain at the centre, rho w^2 L^2 / (8 E)
constexpr double kTurns = 1.5;
constexpr int kSamplesPerTurn = 2000;

std::vector<ValidationResult> bar_spin(const ValidationCase& c, const ElasticSolid& solid, const char* name) {
  const WallClock clock;
  const int n = c.resolution, nl = int(kLengthOverSide * n);
  const double m = c.delta_over_lambda, side = 0.01, lambda = side / n, length = nl * lambda;
  const double dt = c.dt_fraction * validation_critical_dt(solid, lambda, m);
  const double spin = std::sqrt(8 * kPeakStrain * solid.youngs / (solid.density * length * length));
  const double turn = 2 * M_PI / spin;
  const int64_t chunk = std::max<int64_t>(1, int64_t(turn / (dt * kSamplesPerTurn)));

  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = validation_material(solid, lambda, m, c.surface_correction, c.surface_ghosts);
  in.step.dt = real(dt);
  const double corner[3] = {-0.5 * length, -0.5 * side, -0.5 * side};
  std::vector<int> left, right;
  for_each_cube(nl, n, n, lambda, corner, [&](int i, int, int, double x, double y, double z) {
    const size_t p = add_cube(in.particles, x, y, z, lambda, solid, 1.0);
    in.particles.velocity[p] = {real(-spin * y), real(spin * x), 0};
    if (i == 0) left.push_back(int(p));
    if (i == nl - 1) right.push_back(int(p));
  });
  const auto& rest = in.particles.rest;
  const auto& mass = in.particles.mass;

  std::string stable_note;
  auto engine = validation_engine(c, in, stable_note);
  ParticleState s;
  auto centroid = [&](const std::vector<int>& layer, int axis) {
    double sum = 0;
    for (int p : layer) {
      const Vec3 x = rest[p] + s.disp[p];
      sum += axis == 0 ? x.x : x.y;
    }
    return sum / double(layer.size());
  };
  auto angular_momentum = [&]() {
    double l = 0;
    for (size_t p = 0; p < rest.size(); ++p) {
      const Vec3 x = rest[p] + s.disp[p];
      l += mass[p] * (double(x.x) * s.vel[p].y - double(x.y) * s.vel[p].x);
    }
    return l;
  };
  engine->read_state(s);
  const double momentum0 = angular_momentum();

  const double rest_span = length - lambda;
  const int64_t turn_steps = int64_t(std::llround(turn / dt));
  const int64_t start = int64_t(std::llround(0.5 * turn / dt)),
                end = int64_t(std::llround(kTurns * turn / dt));
  engine->advance(start);
  double stretch_sum = 0;
  int64_t samples = 0;
  while (engine->step() < end) {
    engine->advance(std::min(chunk, end - engine->step()));
    engine->read_state(s);
    const double dx = centroid(right, 0) - centroid(left, 0), dy = centroid(right, 1) - centroid(left, 1);
    stretch_sum += std::hypot(dx, dy) - rest_span;
    ++samples;
  }
  const double stretch = stretch_sum / double(samples);

  const double a = 0.5 * rest_span;
  const double reference =
      2 * solid.density * spin * spin * (length * length * a / 4 - a * a * a / 3) / (2 * solid.youngs);
  std::vector<ValidationResult> out = {
      make_result(std::string(name) + "/stretch", stretch, reference),
      make_result(std::string(name) + "/angular_momentum", angular_momentum() / momentum0, 1.0)};
  return stamped(std::move(out), in, *engine, clock,
                 std::to_string(kTurns) + " turns of " + std::to_string(turn_steps) + " steps" + stable_note);
}

}  // namespace

std::vector<ValidationResult> run_bar_spin_lps(const ValidationCase& c) {
  return bar_spin(c, {70e9, 0.3, 2700, true}, "bar_spin_lps");
}

}  // namespace pd
