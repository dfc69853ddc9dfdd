#include "host/validation/lattice.h"

#include <cstdio>
#include <stdexcept>

#include "cuda/engine/material.h"
#include "cuda/engine/stable_step.h"

namespace pd {

Material validation_material(const ElasticSolid& s, double lambda, double m,
                             std::optional<bool> surface_correction, bool ghosts) {
  Material mat;
  mat.horizon = real(m * lambda);
  mat.spacing = real(lambda);
  mat.contact_spacing = real(lambda);
  mat.partial_volumes = 1;
  if (!s.state_based) {
    mat.model = kBondBased;
    mat.micromodulus = real(pmb_lattice_micromodulus(s.bulk(), mat));
    mat.surface_correction = surface_correction.value_or(!ghosts) ? 1 : 0;
    mat.ghost_correction = ghosts ? 1 : 0;
    mat.axial_sum = real(lattice_family_sums(mat).axial_sum);
    return mat;
  }
  mat.model = kStateBased;
  mat.bulk_modulus = real(s.bulk());
  mat.shear_modulus = real(s.shear());
  mat.chen_fracture = 0;  // the stretch criterion: validation bonds never reach their limit
  mat.surface_correction = surface_correction.value_or(false) ? 1 : 0;
  mat.ghost_correction = ghosts ? 1 : 0;
  mat.axial_sum = real(lattice_family_sums(mat).bond_sum / 3);
  return mat;
}

double validation_critical_dt(const ElasticSolid& s, double lambda, double m) {
  return s.state_based ? lps_critical_time_step(s.density, s.bulk(), s.shear(), m * lambda)
                       : pmb_critical_time_step(s.density, s.bulk(), m * lambda);
}

std::unique_ptr<Engine> validation_engine(const ValidationCase& c, const SimulationInput& in,
                                          std::string& stable_note) {
  auto engine = make_engine(c.backend, in);
  stable_note.clear();
  if (!c.surface_ghosts) return engine;
  const double stable = measure_stable_step(*engine, in).seconds, dt = double(in.step.dt);
  if (dt > stable) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "dt fraction %.3g exceeds the stable step measured with ghosts (allowed: at most %.3g)",
                  c.dt_fraction, c.dt_fraction * stable / dt);
    throw std::invalid_argument(msg);
  }
  char note[64];
  std::snprintf(note, sizeof note, "; dt %.2f of the measured stable step", dt / stable);
  stable_note = note;
  return engine;
}

size_t add_cube(ParticleSet& ps, double x, double y, double z, double lambda, const ElasticSolid& s,
                double strain_limit, uint8_t flags) {
  const double vol = lambda * lambda * lambda;
  return ps.add({real(x), real(y), real(z)}, {0, 0, 0}, real(vol), real(s.density * vol), real(strain_limit),
                0, 0, flags);
}

double fit_slope(const double* x, const double* y, size_t n) {
  double mx = 0, my = 0;
  for (size_t k = 0; k < n; ++k) mx += x[k] / double(n), my += y[k] / double(n);
  double sxy = 0, sxx = 0;
  for (size_t k = 0; k < n; ++k) sxy += (x[k] - mx) * (y[k] - my), sxx += (x[k] - mx) * (x[k] - mx);
  return sxx > 0 ? sxy / sxx : 0;
}

}  // namespace pd
