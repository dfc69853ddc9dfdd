// The stable time step of velocity Verlet measured on the engine's own forces, where the
// families' estimate (Engine::critical_time_step, a sum of each particle's bond stiffnesses) is
// far from the truth: the ghost correction's bonds reach the whole family through the fit's
// extrapolation, and the estimate cannot follow them.
//
// Verlet is stable for dt < 2 / omega_max, omega_max^2 the largest eigenvalue of M^-1 K (K the
// stiffness, linearized at the engine's state). It is found by Lanczos on the symmetric form
// M^-1/2 K M^-1/2, each product one force pass of the engine itself on a small displacement
// (a strain of about kProbeStrain): the state is saved, each probe's particles restored with that
// displacement, no velocity and no force (Engine::restore_particles: the bonds, which the probes
// do not break, stay on the backend), one step taken (which leaves the positions where they are
// and computes the forces there) and the forces read back; the whole state saved is restored at
// the end, so the run goes on bit for bit as if it had not been probed. Held anchored particles
// are the problem's fixed degrees of freedom.
#pragma once

#include <cmath>

#include "cuda/engine/engine.h"

namespace pd {

struct StableStepOptions {
  int max_iterations = 80;      // Lanczos steps at most (each one force pass)
  double tolerance = 1e-3;      // stop when the top Ritz pair's residual is below this of its value
  unsigned long long seed = 1;  // the start vector's
};

struct StableStep {
  double lambda_max = 0;      // largest eigenvalue of M^-1 K [1/s^2]: the top Ritz value plus its residual
  double residual = 0;        // the top Ritz pair's residual bound [1/s^2]
  int iterations = 0;         // Lanczos steps taken
  double seconds = INFINITY;  // 2 / sqrt(lambda_max): infinite where nothing is stiff
};

// Strain of the probes' displacements (against the smallest material spacing): far below any
// strain limit or yield, far above the forces' round-off.
constexpr double kProbeStrain = 1e-6;

// The engine's stable step at its current state; `in` is the input it was built from (masses,
// held particles, material spacings).
StableStep measure_stable_step(Engine& engine, const SimulationInput& in,
                               const StableStepOptions& options = {});

// A measured step rounded down to 8 significant bits, so that backends whose forces differ in
// round-off choose the same dt (at most 0.8% shorter).
double rounded_down_step(double seconds);

}  // namespace pd
