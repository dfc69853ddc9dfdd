// Energy accounting of the engine (CPU-reference backend): the balance
//   kinetic + strain + contact + gravity + released - work
// is conserved by velocity Verlet to second order in dt, through fracture, projectile hits
// and moving grips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cuda/engine/engine.h"
#include "cuda/engine/material.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

// A free bar vibrating in its first bending-like mode (smooth velocities): no breaking, no contact.
SimulationInput vibrating_block(bool state_based, double dt_fraction) {
  auto in = state_based ? testing::state_block(16, 4, 4, 1e-3, 0.5, false)
                        : testing::lattice_block(16, 4, 4, 1e-3, 0.5);
  for (size_t i = 0; i < in.particles.size(); ++i)
    in.particles.velocity[i] = {0, real(0.01 * std::cos(M_PI * in.particles.rest[i].x / 15e-3)), 0};
  const Material& m = in.materials.m[0];
  const double dtc = state_based ? lps_critical_time_step(2440, m.bulk_modulus, m.shear_modulus, m.horizon)
                                 : pmb_critical_time_step(2440, 32.81e9, m.horizon);
  in.step.dt = real(dt_fraction * dtc);
  return in;
}

struct EnergyError {
  double drift;      // |mean of the last samples - mean of the first samples| / E0
  double amplitude;  // largest |balance(t) - balance(0)| / E0
};

// Samples the balance 50 times over `duration`; energies relative to the initial kinetic energy.
EnergyError energy_error(const SimulationInput& in, double duration) {
  auto e = make_cpu_engine(in);
  const Energy e0 = e->energy();
  const int64_t steps = int64_t(std::ceil(duration / in.step.dt)), chunk = std::max<int64_t>(1, steps / 50);
  std::vector<double> samples;
  for (int64_t s = 0; s < steps; s += chunk) {
    e->advance(chunk);
    samples.push_back((e->energy().balance() - e0.balance()) / e0.kinetic);
  }
  EnergyError err{0, 0};
  double first = 0, last = 0;
  const size_t w = samples.size() / 5;
  for (size_t k = 0; k < w; ++k)
    first += samples[k] / double(w), last += samples[samples.size() - 1 - k] / double(w);
  err.drift = std::fabs(last - first);
  for (double v : samples) err.amplitude = std::max(err.amplitude, std::fabs(v));
  return err;
}

// Velocity Verlet is symplectic: no secular drift (below 1e-3 at 0.5 dt_c over ~10
// periods of the highest modes), and the bounded oscillation of the energy error falls 4x
// when dt halves.
TEST(EngineEnergy, VerletDriftIsSmallAndSecondOrder) {
  for (bool state : {false, true}) {
    const double duration = 1000 * vibrating_block(state, 0.5).step.dt;
    const EnergyError coarse = energy_error(vibrating_block(state, 0.5), duration);
    const EnergyError fine = energy_error(vibrating_block(state, 0.25), duration);
    std::printf("  %s: drift %.2e, amplitude %.2e at 0.5 dt_c; amplitude %.2e at 0.25 dt_c (ratio %.2f)\n",
                state ? "state-based" : "bond-based", coarse.drift, coarse.amplitude, fine.amplitude,
                coarse.amplitude / fine.amplitude);
    EXPECT_LT(coarse.drift, 1e-3);
    EXPECT_GT(coarse.amplitude / fine.amplitude, 3.0);  // second order: 4 ideally
  }
}

// Bonds broken by pulling a bar apart: the released energy keeps the books. Each break
// happens somewhere inside a step, so the balance error is first order in dt.
TEST(EngineEnergy, BalanceHoldsThroughFracture) {
  double previous = 0;
  for (double scale : {1.0, 0.5, 0.25}) {
    auto in = testing::lattice_block(16, 4, 4, 1e-3, 2e-4);
    for (size_t i = 0; i < in.particles.size(); ++i)
      in.particles.velocity[i] = {real(in.particles.rest[i].x < 8e-3 ? -1 : 1), 0, 0};
    in.step.dt = real(in.step.dt * scale);
    auto e = make_cpu_engine(in);
    const Energy e0 = e->energy();
    e->advance(int64_t(400 / scale));
    const Energy e1 = e->energy();
    ASSERT_GT(e->broken_bonds(), 0);
    const double err = std::fabs(e1.balance() - e0.balance());
    EXPECT_LT(err, 0.25 * e1.released) << "dt scale " << scale;
    if (previous > 0) {
      EXPECT_LT(err, 0.6 * previous) << "dt scale " << scale;
    }
    previous = err;
  }
}

// A projectile does work on the plate; moving grips do work on a bar.
TEST(EngineEnergy, ExternalWorkIsAccounted) {
  auto hit = testing::lattice_block(12, 12, 3, 1e-3, 0.5);
  hit.step.n_projectiles = 1;
  hit.step.projectile[0] = {
      {real(5.5e-3), real(5.5e-3), real(9e-3)}, {0, 0, real(-20)}, real(4e-3), real(1e5)};
  auto pull = testing::lattice_block(16, 4, 4, 1e-3, 0.5);
  for (size_t i = 0; i < pull.particles.size(); ++i)
    if (pull.particles.rest[i].x > 13.5e-3) {
      pull.particles.flags[i] |= kAnchored;
      pull.particles.velocity[i] = {real(0.5), 0, 0};
    }
  for (SimulationInput* in : {&hit, &pull}) {
    auto e = make_cpu_engine(*in);
    const Energy e0 = e->energy();
    e->advance(600);
    const Energy e1 = e->energy();
    EXPECT_GT(e1.work, 0);
    EXPECT_GT(e1.strain + e1.kinetic - e0.kinetic, 0.5 * e1.work);  // the work went into the body
    EXPECT_NEAR(e1.balance(), e0.balance(), 0.02 * e1.work);
  }
}

// A block thrown onto the floor (restitution 0.3): the kinetic energy the floor takes away is
// booked exactly, including the impact's large accelerations.
TEST(EngineEnergy, FloorLossIsAccounted) {
  auto in = testing::lattice_block(6, 6, 6, 1e-3, 0.5);
  for (auto& v : in.particles.velocity) v = {0, real(-2), 0};
  in.step.floor_enabled = 1;
  in.step.floor_height = real(-0.05e-3);
  in.step.restitution = real(0.3);
  auto e = make_cpu_engine(in);
  const Energy e0 = e->energy();
  e->advance(1500);
  const Energy e1 = e->energy();
  EXPECT_LT(e1.work, -0.3 * e0.kinetic);  // the floor took a good part of the energy
  EXPECT_NEAR(e1.balance(), e0.balance(), 0.01 * e0.kinetic);
}

}  // namespace
}  // namespace pd
