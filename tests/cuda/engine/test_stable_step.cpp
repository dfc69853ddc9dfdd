// The stable step measured on the engine (cuda/engine/stable_step.h), on the CPU-reference
// engine: it is the largest eigenvalue of the stiffness assembled column by column from fresh
// engines, velocity Verlet stays bounded just below it and blows up just above it, with and
// without the ghost correction, and probing leaves the run as it would have been.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>

#include "cuda/engine/engine.h"
#include "cuda/engine/stable_step.h"
#include "tests/support/fixtures.h"
#include "tests/support/same_state.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

// A block of PMB or LPS particles, with the ghost correction or none.
// tau: the strain limit (1: no bond breaks).
SimulationInput block(bool state_based, bool ghosts, int nx, int ny, int nz, double tau = 1.0) {
  SimulationInput in = state_based ? testing::state_block(nx, ny, nz, kLambda, tau, false)
                                   : testing::lattice_block(nx, ny, nz, kLambda, tau);
  Material& m = in.materials.m[0];
  m.partial_volumes = 1;
  m.surface_correction = 0;
  m.ghost_correction = ghosts ? 1 : 0;
  return in;
}

// The forces after one step that moves particle `i` by h along axis `a` (velocity h / dt, a step
// so short that the forces move nothing further): an independent way to the stiffness.
std::vector<Vec3> forces_displaced(SimulationInput in, int64_t i, int a, double h) {
  in.step.dt = real(1e-9);
  if (i >= 0) {
    Vec3& v = in.particles.velocity[size_t(i)];
    (a == 0 ? v.x : a == 1 ? v.y : v.z) = real(h * 1e9);
  }
  auto e = make_cpu_engine(in);
  e->advance(1);
  ParticleState s;
  e->read_state(s);
  return s.force;
}

// The largest eigenvalue of M^-1/2 K M^-1/2 with K from 3N displaced engines, and its asymmetry.
struct DenseEigen {
  double lambda_max = 0, asymmetry = 0;
};

DenseEigen dense_largest_eigenvalue(const SimulationInput& in) {
  const int64_t n = int64_t(in.particles.size());
  const double h = 1e-9;  // a strain of 1e-6
  const std::vector<Vec3> f0 = forces_displaced(in, -1, 0, 0);
  Eigen::MatrixXd k(3 * n, 3 * n);
  for (int64_t j = 0; j < n; ++j)
    for (int a = 0; a < 3; ++a) {
      const std::vector<Vec3> f = forces_displaced(in, j, a, h);
      for (int64_t i = 0; i < n; ++i) {
        const Vec3 df = f[size_t(i)] - f0[size_t(i)];
        const double w = 1.0 / std::sqrt(double(in.particles.mass[size_t(i)]) * in.particles.mass[size_t(j)]);
        k(3 * i, 3 * j + a) = -df.x / h * w;
        k(3 * i + 1, 3 * j + a) = -df.y / h * w;
        k(3 * i + 2, 3 * j + a) = -df.z / h * w;
      }
    }
  DenseEigen out;
  out.asymmetry = (k - k.transpose()).norm() / k.norm();
  const Eigen::MatrixXd sym = 0.5 * (k + k.transpose());
  out.lambda_max =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sym, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  return out;
}

// Lanczos against the dense matrix: the largest eigenvalue to its tolerance (the Ritz value from
// below, plus its residual), for each model with and without ghosts.
TEST(StableStep, IsTheStiffnessMatrixsLargestEigenvalue) {
  for (bool state_based : {false, true})
    for (bool ghosts : {false, true}) {
      const SimulationInput in = block(state_based, ghosts, 5, 4, 4);
      const DenseEigen dense = dense_largest_eigenvalue(in);
      auto engine = make_cpu_engine(in);
      StableStepOptions options;
      options.tolerance = 1e-4;
      const StableStep measured = measure_stable_step(*engine, in, options);
      std::printf("  %s%s: lambda_max %.6g (dense %.6g, asymmetry %.1e), %d iterations, step %.4g s\n",
                  state_based ? "LPS" : "PMB", ghosts ? " with ghosts" : "", measured.lambda_max,
                  dense.lambda_max, dense.asymmetry, measured.iterations, measured.seconds);
      EXPECT_LT(dense.asymmetry, 1e-4);  // forces from an energy: a symmetric stiffness
      EXPECT_NEAR(measured.lambda_max / dense.lambda_max, 1.0, 2e-4);
      EXPECT_LT(measured.iterations, options.max_iterations);
    }
}

// Kinetic + strain energy after `steps` of a block whose particles start with random velocities,
// relative to the start, at dt = fraction of the measured stable step.
double energy_growth(bool state_based, bool ghosts, double fraction, int steps) {
  SimulationInput in = block(state_based, ghosts, 8, 6, 6);
  const double stable = measure_stable_step(*make_cpu_engine(in), in).seconds;
  Random rng(3);
  for (auto& v : in.particles.velocity)
    v = {real(rng.uniform() - 0.5), real(rng.uniform() - 0.5), real(rng.uniform() - 0.5)};
  in.step.dt = real(fraction * stable);
  auto engine = make_cpu_engine(in);
  const double e0 = engine->energy().mechanical();
  engine->advance(steps);
  if (engine->first_non_finite() >= 0) return INFINITY;
  return engine->energy().mechanical() / e0;
}

// The measured step is the stability limit itself: velocity Verlet's top mode grows by 1.5 a step
// at 1.02 of it (omega dt = 2.04), and is bounded at 0.97.
TEST(StableStep, VerletIsBoundedJustBelowTheMeasuredStepAndBlowsUpJustAbove) {
  for (bool state_based : {false, true})
    for (bool ghosts : {false, true}) {
      const double below = energy_growth(state_based, ghosts, 0.97, 400);
      const double above = energy_growth(state_based, ghosts, 1.02, 400);
      std::printf("  %s%s: energy ratio after 400 steps at 0.97 %.3g, at 1.02 %.3g\n",
                  state_based ? "LPS" : "PMB", ghosts ? " with ghosts" : "", below, above);
      EXPECT_LT(below, 2.0);
      EXPECT_GT(above, 1e6);
    }
}

// The families' estimate is Gershgorin's bound on the same eigenvalue (Silling & Askari's rate
// is a row sum): never above the measured step without ghosts.
TEST(StableStep, TheFamiliesEstimateIsABoundWithoutGhosts) {
  for (bool state_based : {false, true}) {
    const SimulationInput in = block(state_based, false, 8, 6, 6);
    auto engine = make_cpu_engine(in);
    const double measured = measure_stable_step(*engine, in).seconds;
    std::printf("  %s: measured %.4g s, families %.4g s (%.2fx)\n", state_based ? "LPS" : "PMB", measured,
                engine->critical_time_step(), measured / engine->critical_time_step());
    if (!state_based) {
      EXPECT_GE(measured, engine->critical_time_step());
    }
  }
}

void expect_same_state(Engine& a, Engine& b) {
  ParticleState sa, sb;
  a.read_state(sa);
  b.read_state(sb);
  testing::expect_same_particles(sa, sb);
  EXPECT_EQ(a.step(), b.step());
  EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
}

// Probing restores the state: a run probed at its start, then given a new dt, goes on bit for bit
// as one built with that dt.
TEST(StableStep, LeavesTheRunAsIfUnprobed) {
  SimulationInput in = block(true, true, 8, 6, 6, 2e-4);  // some bonds break
  Random rng(5);
  for (auto& v : in.particles.velocity)  // fast enough to break bonds
    v = real(100) * Vec3{real(rng.uniform() - 0.5), real(rng.uniform() - 0.5), real(rng.uniform() - 0.5)};
  auto probed = make_cpu_engine(in);
  const double dt = 0.5 * measure_stable_step(*probed, in).seconds;
  probed->set_time_step(dt);
  in.step.dt = real(dt);
  auto plain = make_cpu_engine(in);
  probed->advance(60);
  plain->advance(60);
  EXPECT_GT(plain->broken_bonds(), 0);
  expect_same_state(*probed, *plain);
}

// Probed mid-run, while bonds break (some at their limit, which a probe may break and the probe
// puts back), the run goes on bit for bit as one never probed.
TEST(StableStep, MidRunProbeLeavesTheRunAsIfUnprobed) {
  SimulationInput in = block(false, true, 8, 6, 6, 2e-4);
  Random rng(6);
  for (auto& v : in.particles.velocity)
    v = real(100) * Vec3{real(rng.uniform() - 0.5), real(rng.uniform() - 0.5), real(rng.uniform() - 0.5)};
  in.step.dt = real(2e-8);
  auto probed = make_cpu_engine(in), plain = make_cpu_engine(in);
  probed->advance(30);
  plain->advance(30);
  const int64_t broken = plain->broken_bonds();
  const StableStep s = measure_stable_step(*probed, in);
  EXPECT_GT(s.lambda_max, 0);
  probed->advance(30);
  plain->advance(30);
  EXPECT_GT(broken, 0);
  EXPECT_GT(plain->broken_bonds(), broken);
  expect_same_state(*probed, *plain);
}

TEST(StableStep, RoundedDownTo8Bits) {
  EXPECT_EQ(rounded_down_step(1.0), 1.0);
  EXPECT_EQ(rounded_down_step(0.75), 0.75);
  EXPECT_EQ(rounded_down_step(1.0 - 1e-9), 255.0 / 256.0);
  const double t = 3.3e-8, r = rounded_down_step(t);
  EXPECT_LE(r, t);
  EXPECT_GT(r, t * (1 - 1.0 / 128));
  EXPECT_TRUE(std::isinf(rounded_down_step(INFINITY)));
}

}  // namespace
}  // namespace pd
