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
// With scattered particles (ValidationCase::particles) the same box is filled with Voronoi cells
// or TetGen tets of about the grid's spacing W / n, the grips are the particles within their
// length of the ends, and the gauge those within half a width of the centre; the horizon is m
// times the particles' median nearest-neighbour distance, as in a scene (scene_setup.cpp).
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/geometry/shapes.h"
#include "host/geometry/tet_body_solids.h"
#include "host/geometry/tet_particles.h"
#include "host/geometry/voronoi_particles.h"
#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

// The box of edge lengths `size` centred on the origin, filled with Voronoi cells or tets of
// spacing about `spacing` (the scenes' rules: Voronoi sites at least `spacing` apart, tets of at
// most twice its cube), with each particle's nearest-neighbour distance.
ParticleGeometry scattered_box(const std::string& kind, const Vec3d& size, double spacing) {
  constexpr int64_t kMaxParticles = 50'000'000;
  constexpr uint64_t kSeed = 1;
  const TriMesh box = box_mesh(size);
  ParticleGeometry g;
  if (kind == "voronoi") {
    g = voronoi_particles(box, spacing, kSeed, kMaxParticles, "tension bar");
  } else if (kind == "tets") {
    TetgenOptions options;
    options.max_volume = 2 * spacing * spacing * spacing;
    g = tet_particles(box, options, kMaxParticles, "tension bar");
  } else {
    throw std::invalid_argument("particles '" + kind + "' (allowed: grid, voronoi, tets)");
  }
  compute_lambda(g);
  return g;
}

constexpr double kFreeLengthOverWidth = 4;
constexpr double kFinalStrain = 5e-4;
constexpr double kWidthTransits = 40;  // run length in lateral transit times W / c0
constexpr int kSamples = 40;           // over the second half of the run

std::vector<ValidationResult> tension_bar(const ValidationCase& c, const ElasticSolid& solid,
                                          const char* name) {
  const WallClock clock;
  const int n = c.resolution;
  const double m = c.delta_over_lambda, width = 0.01, grid_spacing = width / n;
  const int grip = int(std::ceil(m)), nx = int(kFreeLengthOverWidth * n) + 2 * grip;
  const double half = 0.5 * nx * grid_spacing;
  const bool grid = c.particles == "grid";
  const ParticleGeometry scattered =
      grid ? ParticleGeometry{} : scattered_box(c.particles, {2 * half, width, width}, grid_spacing);
  const double lambda = grid ? grid_spacing : median_nearest_distance(scattered);
  const double c0 = std::sqrt(solid.youngs / solid.density);
  const double dt = c.dt_fraction * validation_critical_dt(solid, lambda, m);
  const int64_t steps = int64_t(std::ceil(kWidthTransits * width / (c0 * dt)));
  const double rate = kFinalStrain / (double(steps) * dt);

  // The bar, centred on the origin; grips at both ends; gauge = the central width.
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = validation_material(solid, lambda, m, c.surface_correction, c.surface_ghosts);
  if (!grid) in.materials.m[0].contact_spacing = real(scattered.min_distance);
  in.step.dt = real(dt);
  std::vector<int> left, right, gauge;
  const double grip_end = half - grip * grid_spacing;
  const auto add = [&](double x, double y, double z, double volume) {
    const bool is_grip = std::fabs(x) > grip_end;
    const size_t p = in.particles.add({real(x), real(y), real(z)}, {real(rate * x), 0, 0}, real(volume),
                                      real(solid.density * volume), 1, 0, 0, is_grip ? kAnchored : 0);
    if (x < -grip_end) left.push_back(int(p));
    if (x > grip_end) right.push_back(int(p));
    if (std::fabs(x) < 0.5 * width) gauge.push_back(int(p));
  };
  if (grid) {
    const double corner[3] = {-half, -0.5 * width, -0.5 * width};
    const double cube = lambda * lambda * lambda;
    for_each_cube(nx, n, n, lambda, corner,
                  [&](int, int, int, double x, double y, double z) { add(x, y, z, cube); });
  } else {
    for (size_t i = 0; i < scattered.size(); ++i)
      add(scattered.position[i][0], scattered.position[i][1], scattered.position[i][2], scattered.volume[i]);
    if (scattered.kind == ElementKind::tet && c.surface_ghosts) {  // as a scene's tet body (scene_setup.cpp)
      auto solids = std::make_shared<TetBodySolids>();
      solids->add(0, scattered.tets);
      in.body_solids = std::move(solids);
    }
  }

  std::string stable_note;
  auto engine = validation_engine(c, in, stable_note);
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
  const std::string problem = grid ? std::string(name) : std::string(name) + "_" + c.particles;
  std::vector<ValidationResult> out = {make_result(problem + "/elongation", measured, reference),
                                       make_result(problem + "/poisson", nu, solid.nu())};
  char note[160];
  std::snprintf(note, sizeof note, "E_measured %.4g GPa; lambda %.4g mm (W / %.2f)", modulus / 1e9,
                lambda * 1e3, width / lambda);
  return stamped(std::move(out), in, *engine, clock, note + stable_note);
}

}  // namespace

std::vector<ValidationResult> run_tension_bar_pmb(const ValidationCase& c) {
  return tension_bar(c, kGlass, "tension_bar_pmb");
}

// A state-based solid with nu = 0.3 (aluminium-like constants).
std::vector<ValidationResult> run_tension_bar_lps(const ValidationCase& c) {
  return tension_bar(c, {70e9, 0.3, 2700, true}, "tension_bar_lps");
}

}  // namespace pd
