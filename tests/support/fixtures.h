// Small simulation inputs shared by the CPU and GPU test suites.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "cuda/engine/material.h"
#include "cuda/engine/particle_set.h"
#include "host/geometry/random.h"

namespace pd::testing {

// A glass-like PMB material at spacing `lambda`, horizon `m` lambda.
inline Material glass_material(double lambda, double m = 3.0, bool partial = true) {
  Material mat;
  mat.horizon = real(m * lambda);
  mat.spacing = real(lambda);
  mat.contact_spacing = real(lambda);
  mat.micromodulus = real(pmb_micromodulus(32.81e9, m * lambda));
  mat.compression_alpha = real(0.25);
  mat.partial_volumes = partial ? 1 : 0;
  return mat;
}

// An nx x ny x nz simple-cubic block of cubes of side lambda, optionally jittered.
inline SimulationInput lattice_block(int nx, int ny, int nz, double lambda, double tau = 1e-3,
                                     double jitter = 0, uint64_t seed = 7) {
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = glass_material(lambda);
  Random rng(seed);
  const double vol = lambda * lambda * lambda;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        auto c = [&](int n) { return (n + jitter * (rng.uniform() - 0.5)) * lambda; };
        in.particles.add({real(c(i)), real(c(j)), real(c(k))}, {0, 0, 0}, real(vol), real(2440 * vol),
                         real(tau), 0, 0);
      }
  in.step.dt = real(0x1p-23);
  return in;
}

// The same block with a state-based material (E = 70 GPa, nu = 0.3), optionally plastic
// (sigma_Y = 200 MPa, limit 0.05) and damage-weighted (Chen alpha = 1).
inline SimulationInput state_block(int nx, int ny, int nz, double lambda, double tau, bool plastic,
                                   double jitter = 0, uint64_t seed = 7) {
  SimulationInput in = lattice_block(nx, ny, nz, lambda, tau, jitter, seed);
  Material& m = in.materials.m[0];
  m = Material();
  m.model = kStateBased;
  m.horizon = real(3 * lambda);
  m.spacing = real(lambda);
  m.contact_spacing = real(lambda);
  m.bulk_modulus = real(70e9 / (3 * 0.4));
  m.shear_modulus = real(70e9 / 2.6);
  m.damage_alpha = 1;
  if (plastic) {
    m.plastic = 1;
    m.yield_psi0 = real(yield_psi0(200e6, 3 * lambda));
    m.plastic_limit = real(0.05);
  }
  return in;
}

// The block of nx particles across x (spacing lambda) pulled apart at +-v about its middle:
// bonds break across it.
inline SimulationInput pulled_apart(SimulationInput in, int nx, double lambda, double v) {
  for (size_t i = 0; i < in.particles.size(); ++i)
    in.particles.velocity[i] = {real(in.particles.rest[i].x < 0.5 * nx * lambda ? -v : v), 0, 0};
  return in;
}

// The bonds across the plane x = x0 weakened to `strength` (two triangles covering it).
inline void weaken_plane(SimulationInput& in, double x0, double strength) {
  CutTriangle a, b;
  a.corner = {{{x0, -1, -1}, {x0, 1, -1}, {x0, 1, 1}}};
  b.corner = {{{x0, -1, -1}, {x0, 1, 1}, {x0, -1, 1}}};
  a.strength = b.strength = strength;
  in.cuts.push_back(a);
  in.cuts.push_back(b);
}

// Total momentum of `vel` with the input's masses, and the sum of |m v| (its scale).
inline std::array<double, 3> total_momentum(const SimulationInput& in, const std::vector<Vec3>& vel,
                                            double* scale = nullptr) {
  std::array<double, 3> p{0, 0, 0};
  double s = 0;
  for (size_t i = 0; i < vel.size(); ++i) {
    const double m = in.particles.mass[i];
    p[0] += m * vel[i].x;
    p[1] += m * vel[i].y;
    p[2] += m * vel[i].z;
    s += m * length(vel[i]);
  }
  if (scale) *scale = s;
  return p;
}

inline double total_mass(const SimulationInput& in) {
  double m = 0;
  for (real v : in.particles.mass) m += v;
  return m;
}

}  // namespace pd::testing
