// The surface correction (cuda/kernels/surface_correction.h), through the CPU engine:
// under a uniform uniaxial strain a block stores the energy of as much interior material, along
// each axis; the corrected bonds keep momentum and energy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/engine/material.h"
#include "host/geometry/random.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

// A block nx x ny x nz of the glass material with the lattice micromodulus, with or without the
// correction.
SimulationInput block(int nx, int ny, int nz, bool correction, double jitter = 0) {
  SimulationInput in = testing::lattice_block(nx, ny, nz, kLambda, 1.0, jitter);
  Material& m = in.materials.m[0];
  m.micromodulus = real(pmb_lattice_micromodulus(32.81e9, m));
  m.surface_correction = correction ? 1 : 0;
  m.axial_sum = real(lattice_family_sums(m).axial_sum);
  return in;
}

// The strain energy after one step from a velocity field that stretches the block uniformly by
// `strain` along `axis` (the first Verlet step moves every particle by v dt: no force acts yet),
// over the energy of as much interior material, c strain^2 A / 4 per unit volume (A the
// interior family's axial sum).
double energy_ratio(SimulationInput in, int axis, double strain) {
  const Material& m = in.materials.m[0];
  const double dt = double(in.step.dt);
  double mean = 0;
  for (size_t i = 0; i < in.particles.size(); ++i) mean += double((&in.particles.rest[i].x)[axis]);
  mean /= double(in.particles.size());
  for (size_t i = 0; i < in.particles.size(); ++i) {
    Vec3 v{0, 0, 0};
    (&v.x)[axis] = real(strain * (double((&in.particles.rest[i].x)[axis]) - mean) / dt);
    in.particles.velocity[i] = v;
  }
  auto engine = make_cpu_engine(in);
  engine->advance(1);
  const double volume = double(in.particles.size()) * kLambda * kLambda * kLambda;
  const double interior = 0.25 * double(m.micromodulus) * strain * strain * lattice_family_sums(m).axial_sum;
  return engine->energy().strain / (interior * volume);
}

// A 12 x 8 x 6 block, delta = 3 lambda: every particle lies within two horizons of a face, so
// without the correction the block stores far less than interior material does (the faces' half
// families, the edges' quarters): measured 34-44% less. With it each particle's three axial sums
// match the interior's up to what the last of the fixed-point rounds leaves (the rounds' study in
// surface_correction.h: the layer under the surface a few percent stiff): measured +1.3% along
// the block's length, +2.9% across. Tolerance 4%.
TEST(SurfaceCorrection, UniformStretchStoresTheInteriorEnergyAlongEachAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    const double on = energy_ratio(block(12, 8, 6, true), axis, 1e-4);
    const double off = energy_ratio(block(12, 8, 6, false), axis, 1e-4);
    std::printf("  axis %d: energy / interior energy %.4f with the correction, %.4f without\n", axis, on,
                off);
    EXPECT_NEAR(on, 1.0, 0.04) << axis;
    EXPECT_LT(off, 0.8) << axis;
  }
}

// Irregular particles (as tets and Voronoi cells are) get the correction from their own families:
// a block jittered by 0.3 lambda stores, along each axis, what the regular block does with the
// correction (measured 0.1-0.2% apart, against 34-45% below without it); tolerance 3%, the
// regular block's own residual.
TEST(SurfaceCorrection, IrregularParticlesAreCorrectedAsRegularOnes) {
  for (int axis = 0; axis < 3; ++axis) {
    const double regular = energy_ratio(block(12, 8, 6, true), axis, 1e-4);
    const double jittered = energy_ratio(block(12, 8, 6, true, 0.3), axis, 1e-4);
    const double plain = energy_ratio(block(12, 8, 6, false, 0.3), axis, 1e-4);
    std::printf(
        "  axis %d: energy / interior energy, jittered %.4f (regular %.4f, jittered uncorrected %.4f)\n",
        axis, jittered, regular, plain);
    EXPECT_NEAR(jittered / regular, 1.0, 0.03) << axis;
  }
}

// The net force on the particles, each component against the sum of the forces' magnitudes: zero
// to float round-off where the bond forces cancel in pairs.
void expect_no_net_force(Engine& engine) {
  ParticleState s;
  engine.read_state(s);
  double sum[3] = {0, 0, 0}, magnitude = 0;
  for (const Vec3& f : s.force) {
    sum[0] += f.x, sum[1] += f.y, sum[2] += f.z;
    magnitude += std::sqrt(double(dot(f, f)));
  }
  ASSERT_GT(magnitude, 0);
  for (double c : sum) EXPECT_LT(std::fabs(c), 1e-5 * magnitude);
}

// The block vibrating in a smooth transverse mode at 0.5 of its families' stable step: the largest
// error of the energy balance over 1000 steps, relative to the kinetic energy; `engine` is left
// after them.
double largest_energy_error(SimulationInput in, std::unique_ptr<Engine>& engine) {
  for (size_t i = 0; i < in.particles.size(); ++i)
    in.particles.velocity[i] = {0, real(0.01 * std::cos(M_PI * in.particles.rest[i].x / 15e-3)), 0};
  in.step.dt = real(0.5 * make_cpu_engine(in)->critical_time_step());
  engine = make_cpu_engine(in);
  const Energy e0 = engine->energy();
  double worst = 0;
  for (int k = 0; k < 50; ++k) {
    engine->advance(20);
    worst = std::fmax(worst, std::fabs(engine->energy().balance() - e0.balance()) / e0.kinetic);
  }
  std::printf("  largest energy error over 1000 steps at 0.5 dt_c: %.2e of the kinetic energy\n", worst);
  return worst;
}

// The factor is the same from both ends of a bond, so the bond forces cancel in pairs: the total
// force on a free jittered block with random velocities stays zero to float round-off.
TEST(SurfaceCorrection, CorrectedBondsKeepMomentum) {
  SimulationInput in = block(7, 6, 5, true, 0.2);
  Random rng(3);
  for (Vec3& v : in.particles.velocity)
    v = {real(rng.uniform() - 0.5), real(rng.uniform() - 0.5), real(rng.uniform() - 0.5)};
  auto engine = make_cpu_engine(in);
  engine->advance(3);
  expect_no_net_force(*engine);
}

// Still a pair potential: velocity Verlet keeps the energy balance of a vibrating corrected
// block without drift (as EngineEnergy.VerletDriftIsSmallAndSecondOrder for the plain model).
TEST(SurfaceCorrection, CorrectedBlockKeepsItsEnergy) {
  std::unique_ptr<Engine> engine;
  EXPECT_LT(largest_energy_error(block(16, 4, 4, true), engine), 1e-3);
}

// The state-based solid with the correction (its influence function times the bond's factor) still
// derives its forces from an energy: the momentum and the energy balance hold as without it.
TEST(SurfaceCorrection, StateBasedBlockKeepsMomentumAndEnergy) {
  SimulationInput in = testing::state_block(16, 4, 4, kLambda, 1.0, false);
  Material& m = in.materials.m[0];
  m.surface_correction = 1;
  m.axial_sum = real(lattice_family_sums(m).bond_sum / 3);
  std::unique_ptr<Engine> engine;
  EXPECT_LT(largest_energy_error(in, engine), 1e-3);
  expect_no_net_force(*engine);
}

// The strain energy and the forces of `in` after `steps` steps from a velocity field that stretches
// it along x and shears it in y.
struct Response {
  double strain = 0;
  std::vector<Vec3> force;
};
Response stretched_response(SimulationInput in, int steps) {
  for (size_t i = 0; i < in.particles.size(); ++i) {
    const Vec3 x = in.particles.rest[i];
    in.particles.velocity[i] = {real(0.02 * x.x / 16e-3), real(0.01 * x.z / 6e-3), 0};
  }
  auto engine = make_cpu_engine(in);
  engine->advance(steps);
  ParticleState s;
  engine->read_state(s);
  return {engine->energy().strain, s.force};
}

// A lattice body with the correction against the same body with explicit families: the first
// has rows of factors, far fewer than particles, the second none; both give the same response, the
// strain energy within `energy_tolerance` (relative), each force within `force_tolerance` of the
// largest.
void expect_rows_hold_the_slots_factors(const SimulationInput& lattice, double energy_tolerance = 1e-5,
                                        double force_tolerance = 1e-4) {
  const int64_t rows = make_cpu_engine(lattice)->family_stats().surface_rows;
  std::printf("  %lld rows of factors for %zu particles\n", (long long)rows, lattice.particles.size());
  EXPECT_GT(rows, 0);
  EXPECT_LT(rows, int64_t(lattice.particles.size() / 2));
  SimulationInput listed = lattice;
  listed.lattice_families = false;
  EXPECT_EQ(make_cpu_engine(listed)->family_stats().surface_rows, 0);
  const Response a = stretched_response(lattice, 10), b = stretched_response(listed, 10);
  std::printf("  strain energy: lattice rows %.7e J, slots %.7e J\n", a.strain, b.strain);
  EXPECT_NEAR(a.strain / b.strain, 1.0, energy_tolerance);
  double worst = 0, largest = 0;
  for (size_t i = 0; i < a.force.size(); ++i) {
    worst = std::fmax(worst, double(length(a.force[i] - b.force[i])));
    largest = std::fmax(largest, double(length(b.force[i])));
  }
  std::printf("  largest force difference %.2e of the largest force\n", worst / largest);
  EXPECT_LT(worst, force_tolerance * largest);
}

// Lattice particles read their bonds' factors from rows of a table, one per class of particles
// placed alike relative to the faces, explicit families at their slots: both give the same
// response, and a long block has far fewer rows than particles. The glass has partial volumes,
// which a lattice bond takes from its stencil entry and a listed one from its slot, where its
// factor is stored times its partial volume (surface_correction.h folds_partial_volume) in the
// same steps of 2^-12: a bond's g beta is at least about 1/2 (beta falls to 1/2 at |xi| = delta,
// the family's edge), so the step moves it by at most 2^-13 / (1/2) = 2.4e-4 of itself, and a sum
// of bonds' energies by as much (measured 7e-6); a force, a difference of bonds' pulls, by that
// share of their magnitudes, about ten times its own at the faces (measured 6e-5 of the largest).
TEST(SurfaceCorrection, LatticeRowsHoldTheBondsFactors) {
  expect_rows_hold_the_slots_factors(block(120, 8, 6, true), 2.4e-4, 2.4e-3);
}

// The state-based kernels read a lattice bond's factor from the same rows (the stored bits of its
// slot, without the slot's index): the response equals the listed families' as for bond-based
// bonds (measured 7e-8 in energy).
TEST(SurfaceCorrection, StateBasedLatticeRowsHoldTheBondsFactors) {
  SimulationInput lattice = testing::state_block(40, 8, 6, kLambda, 1.0, false);
  Material& m = lattice.materials.m[0];
  m.surface_correction = 1;
  m.axial_sum = real(lattice_family_sums(m).bond_sum / 3);
  expect_rows_hold_the_slots_factors(lattice);
}

// A pre-crack is a crack, not a face of the body: its faces are not corrected (the factors come
// from the families before the cuts), so a block cut half through along the stretch stores less
// than the uncut block, by the share of the cut bonds (measured 5.1%), where corrected faces
// would give most of it back.
TEST(SurfaceCorrection, PreCracksAreNotCorrected) {
  SimulationInput uncut = block(24, 12, 6, true), cut = uncut;
  // The plane y = 5.5 lambda from x = -1 to 12 lambda, through the thickness.
  const double l = kLambda, y = 5.5 * l;
  cut.cuts.push_back({{{{-l, y, -l}, {12 * l, y, -l}, {12 * l, y, 7 * l}}}, 0, -1});
  cut.cuts.push_back({{{{-l, y, -l}, {12 * l, y, 7 * l}, {-l, y, 7 * l}}}, 0, -1});
  const double whole = stretched_response(uncut, 5).strain, split = stretched_response(cut, 5).strain;
  std::printf("  strain energy: uncut %.5e J, cut %.5e J (%.2f%% less)\n", whole, split,
              100 * (1 - split / whole));
  EXPECT_LT(split, 0.99 * whole);
}

}  // namespace
}  // namespace pd
