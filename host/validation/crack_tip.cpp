// Crack-tip toughness (docs/validation.md, "crack_tip_pmb"): the stress intensity at which a sharp
// crack starts to grow in a PMB solid, against Griffith's K_Ic = sqrt(E G0), with nothing else in
// the problem: no specimen geometry factor, no net section, no bending. A disc of glass of radius R
// (R / lambda = the resolution) and 2 ceil(delta / lambda) layers thick holds a straight
// through-crack along y = 0 from its edge to the centre (a cut: the bonds crossing the half-plane
// x < 0 are removed). A ring of ceil(delta / lambda) layers outside R is anchored and moves with
// Williams' mode I field of linear elastic fracture mechanics (plane stress, kappa =
// (3 - nu) / (1 + nu)),
//   u_x = K / (2 mu) sqrt(r / 2 pi) cos(theta / 2) (kappa - 1 + 2 sin^2(theta / 2)),
//   u_y = K / (2 mu) sqrt(r / 2 pi) sin(theta / 2) (kappa + 1 - 2 cos^2(theta / 2)),
// with K rising at a constant rate from 0 to 2 K_Ic over 40 transit times R / c0 (every particle
// starting with the field's velocity, so no wave is launched); the standard "boundary layer"
// model of the crack-tip literature. PMB with the lattice critical stretch, no strain-limit scatter.
//   measured: K when a bond across the crack's plane breaks at least delta ahead of the tip (the
//   crack grows); the note adds K at the first broken bond (the tip bond alone, which does not make
//   a crack) and at 2 and 4 delta, where the run stops.
//   reference: K_Ic = sqrt(E G0) (plane stress; a plate two horizons thick lies between plane
//   stress and plane strain, whose K_Ic is 1 / sqrt(1 - nu^2) = 3.3% higher).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "cuda/engine/material.h"
#include "host/validation/lattice.h"
#include "host/validation/validation.h"

namespace pd {

namespace {

constexpr double kRadius = 0.02;        // R [m]
constexpr double kRadiusTransits = 40;  // time for K to reach 2 K_Ic, in transit times R / c0
constexpr int kSamples = 400;

// Williams' mode I displacement per unit K at (x, y) from the tip, plane stress.
Vec3 mode_one_field(double x, double y, const ElasticSolid& s) {
  const double r = std::hypot(x, y), theta = std::atan2(y, x), nu = s.nu();
  const double kappa = (3 - nu) / (1 + nu), scale = std::sqrt(r / (2 * M_PI)) / (2 * s.shear());
  const double c = std::cos(0.5 * theta), sn = std::sin(0.5 * theta);
  return {real(scale * c * (kappa - 1 + 2 * sn * sn)), real(scale * sn * (kappa + 1 - 2 * c * c)), 0};
}

// How far the crack has run past the tip: the largest midpoint x of the broken bonds across the
// plane y = 0 within the disc (0: none past it).
double crack_extension(const BondLists& bonds, const std::vector<Vec3>& rest, double radius) {
  double ahead = 0;
  for_each_broken_bond(bonds, [&](int32_t i, int32_t j) {
    const Vec3 p = rest[size_t(i)], q = rest[size_t(j)];
    const double x = 0.5 * (double(p.x) + double(q.x));
    if ((p.y < 0) != (q.y < 0) && x < radius) ahead = std::max(ahead, x);
  });
  return ahead;
}

}  // namespace

std::vector<ValidationResult> run_crack_tip_pmb(const ValidationCase& c) {
  const WallClock clock;
  const ElasticSolid& glass = kGlass;
  const int n = c.resolution;
  const double m = c.delta_over_lambda, lambda = kRadius / n, delta = m * lambda;
  const int ring = int(std::ceil(m)), nz = 2 * ring, half = n + ring;  // cells from the centre to the edge
  const Material mat = validation_material(glass, lambda, m, c.surface_correction, c.surface_ghosts);
  const double s0 = pmb_lattice_critical_stretch(kGlassFractureEnergy, double(mat.micromodulus), mat);
  const double toughness = std::sqrt(glass.youngs * kGlassFractureEnergy);  // K_Ic [Pa m^0.5]
  const double c0 = std::sqrt(glass.youngs / glass.density);
  const double dt = c.dt_fraction * validation_critical_dt(glass, lambda, m);
  const int64_t steps = int64_t(std::ceil(kRadiusTransits * kRadius / (c0 * dt)));
  const double k_rate = 2 * toughness / (double(steps) * dt);  // dK/dt

  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = mat;
  in.step.dt = real(dt);
  // Cells of a 2 half x 2 half x nz block, centred on the tip: x = 0 and y = 0 fall between
  // columns and rows; those within R + ring lambda of the axis are kept, the outer ring anchored.
  const double corner[3] = {-half * lambda, -half * lambda, 0};
  const double outer = kRadius + ring * lambda;
  for_each_cube(2 * half, 2 * half, nz, lambda, corner, [&](int, int, int, double x, double y, double z) {
    const double r = std::hypot(x, y);
    if (r > outer) return;
    const size_t p = add_cube(in.particles, x, y, z, lambda, glass, s0, r > kRadius ? kAnchored : 0);
    in.particles.velocity[p] = real(k_rate) * mode_one_field(x, y, glass);
  });
  // The crack: the half-plane y = 0, x < 0, through the thickness (two triangles reaching past
  // the disc's edge and faces).
  const double x0 = -(outer + 2 * lambda), z0 = -lambda, z1 = nz * lambda + lambda;
  in.cuts.push_back({{{{x0, 0, z0}, {0, 0, z0}, {0, 0, z1}}}, 0, -1});
  in.cuts.push_back({{{{x0, 0, z0}, {0, 0, z1}, {x0, 0, z1}}}, 0, -1});

  // K at the first break and when the crack has run 1, 2 and 4 horizons (an R-curve: a rising
  // one would hold a growing crack back).
  std::string stable_note;
  auto engine = validation_engine(c, in, stable_note);
  const int64_t chunk = std::max<int64_t>(1, steps / kSamples);
  double initiation = 0, grown[3] = {0, 0, 0};
  BondLists bonds;
  while (engine->step() < steps && grown[2] == 0) {
    engine->advance(chunk);
    const double k = k_rate * engine->time();
    if (engine->broken_bonds() == 0) continue;
    if (initiation == 0) initiation = k;
    engine->update_bonds(bonds);
    const double ahead = crack_extension(bonds, in.particles.rest, kRadius);
    for (int g = 0; g < 3; ++g)
      if (grown[g] == 0 && ahead >= double(1 << g) * delta) grown[g] = k;
  }
  std::vector<ValidationResult> out = {make_result("crack_tip_pmb/growth_toughness", grown[0], toughness)};
  char note[260];
  std::snprintf(
      note, sizeof note,
      "K at the first break %.3g, at growth by 1, 2, 4 delta %.3g, %.3g, %.3g MPa m^0.5 (0: not by 2 K_Ic; "
      "K_Ic %.3g); "
      "s0 %.3g; %lld bonds broken; %zu particles, %d layers",
      initiation / 1e6, grown[0] / 1e6, grown[1] / 1e6, grown[2] / 1e6, toughness / 1e6, s0,
      (long long)engine->broken_bonds(), in.particles.size(), nz);
  return stamped(std::move(out), in, *engine, clock, note + stable_note);
}

}  // namespace pd
