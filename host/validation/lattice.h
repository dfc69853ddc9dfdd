// Building blocks of the validation problems: elastic solids, their kernel constants at a
// given spacing, simple-cubic blocks of particles, and a wall clock.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/engine/particle_set.h"
#include "cuda/views.h"
#include "host/validation/validation.h"

namespace pd {

// An isotropic linear elastic solid in engineering constants. Bond-based (PMB) materials have
// nu = 1/4 whatever is asked (DESIGN.md, physics notes), so they take `youngs` and ignore `poisson`.
struct ElasticSolid {
  double youngs = 0;   // E [Pa]
  double poisson = 0;  // nu
  double density = 0;  // rho [kg/m^3]
  bool state_based = false;

  double nu() const { return state_based ? poisson : 0.25; }
  double bulk() const { return youngs / (3 * (1 - 2 * nu())); }
  double shear() const { return youngs / (2 * (1 + nu())); }
};

// The soda-lime glass of the PMB problems (Ha & Bobaru 2010): E 72 GPa, nu 1/4, rho 2440 kg/m^3,
// and its fracture energy G0 [J/m^2].
inline constexpr ElasticSolid kGlass{72e9, 0.25, 2440, false};
inline constexpr double kGlassFractureEnergy = 3.8;

// Kernel constants at spacing lambda and horizon m lambda, with partial volumes (the choice that
// makes the lattice sums closest to the continuum integrals; docs/validation.md); bond-based:
// the lattice's micromodulus; the surface correction as given, else each model's default (on for
// bond-based, off for state-based).
Material validation_material(const ElasticSolid& s, double lambda, double m,
                             std::optional<bool> surface_correction, bool ghosts = false);

// The continuum stable time step estimate of host/material.h for this solid.
double validation_critical_dt(const ElasticSolid& s, double lambda, double m);

// The engine of a validation run. With the ghost correction (c.surface_ghosts), whose stable step
// the continuum estimate does not know, the step is measured on the engine
// (cuda/engine/stable_step.h): a dt past it is refused (std::invalid_argument, with the largest
// dt fraction allowed), and `stable_note` says what fraction of it the run's dt is.
std::unique_ptr<Engine> validation_engine(const ValidationCase& c, const SimulationInput& in,
                                          std::string& stable_note);

// Cube centres of an nx x ny x nz block of cubes of side lambda whose low corner is `corner`;
// calls add(i, j, k, centre) for each, x fastest.
template <class Add>
void for_each_cube(int nx, int ny, int nz, double lambda, const double corner[3], Add add) {
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        add(i, j, k, corner[0] + (i + 0.5) * lambda, corner[1] + (j + 0.5) * lambda,
            corner[2] + (k + 0.5) * lambda);
}

// Appends one cube particle of side lambda at rest, material 0, body 0.
size_t add_cube(ParticleSet& ps, double x, double y, double z, double lambda, const ElasticSolid& s,
                double strain_limit, uint8_t flags = 0);

// Least-squares slope of y against x.
double fit_slope(const double* x, const double* y, size_t n);

class WallClock {
 public:
  WallClock() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// The mean of the x reactions of two grips pulled apart along x (the left one's force on the
// bar, minus the right one's): the axial force the bar carries.
inline double grip_force(const ParticleState& s, const std::vector<int>& left,
                         const std::vector<int>& right) {
  double f = 0;
  for (int p : left) f += 0.5 * s.force[size_t(p)].x;
  for (int p : right) f -= 0.5 * s.force[size_t(p)].x;
  return f;
}

// Calls visit(i, j) for each broken bond of `bonds`, once per stored direction.
template <class Visit>
void for_each_broken_bond(const BondLists& bonds, Visit visit) {
  const BondsView b = bonds.view();
  for (int32_t i = 0; i < b.n; ++i)
    for (int32_t k = 0; k < b.count[i]; ++k) {
      const int32_t nb = b.neighbor[b.slot(i, k)];
      if (nb < 0) visit(i, bond_partner(nb));
    }
}

// `out`, each figure stamped with the run that measured it: its particles, steps, wall time since
// `clock` started and `note`.
inline std::vector<ValidationResult> stamped(std::vector<ValidationResult> out, const SimulationInput& in,
                                             const Engine& engine, const WallClock& clock,
                                             const std::string& note) {
  for (ValidationResult& r : out) {
    r.particles = int64_t(in.particles.size());
    r.steps = engine.step();
    r.wall_s = clock.seconds();
    r.note = note;
  }
  return out;
}

}  // namespace pd
