#include "cuda/engine/material.h"

#include <cmath>

#include "cuda/kernels/family.h"

namespace pd {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double pmb_micromodulus(double bulk_modulus, double horizon) {
  return 18.0 * bulk_modulus / (kPi * std::pow(horizon, 4));
}

LatticeFamilySums lattice_family_sums(const Material& m) {
  const double lambda = double(m.spacing);
  const double radius = double(m.family_radius()) * (1.0 + kHorizonSlack);
  const int reach = int(std::floor(radius / lambda)) + 1;
  LatticeFamilySums sums;
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        if (x == 0 && y == 0 && z == 0) continue;
        const double r0 = lambda * std::sqrt(double(x * x + y * y + z * z));
        if (r0 > radius) continue;
        const double beta = double(volume_fraction(real(r0), m));
        sums.bond_sum += r0 * beta * lambda * lambda * lambda;
        if (z > 0) sums.crossing_sum += z * lambda * r0 * beta * lambda * lambda * lambda;
        const double nx = x * lambda / r0;
        sums.axial_sum += nx * nx * nx * nx * r0 * beta * lambda * lambda * lambda;
      }
  return sums;
}

double pmb_lattice_micromodulus(double bulk_modulus, const Material& m) {
  return 18.0 * bulk_modulus / lattice_family_sums(m).bond_sum;
}

double pmb_lattice_critical_stretch(double fracture_energy, double micromodulus, const Material& m) {
  return std::sqrt(2.0 * fracture_energy / (micromodulus * lattice_family_sums(m).crossing_sum));
}

double pmb_critical_time_step(double density, double bulk_modulus, double horizon) {
  return std::sqrt(2.0 * density * horizon * horizon / (36.0 * bulk_modulus));
}

double lps_critical_stretch(double fracture_energy, double bulk_modulus, double shear_modulus,
                            double horizon) {
  const double k = 3 * shear_modulus + std::pow(0.75, 4) * (bulk_modulus - 5 * shear_modulus / 3);
  return std::sqrt(fracture_energy / (k * horizon));
}

double yield_psi0(double yield_stress, double horizon) {
  return 25 * yield_stress * yield_stress / (8 * kPi * std::pow(horizon, 5));
}

double lps_critical_time_step(double density, double bulk_modulus, double shear_modulus, double horizon) {
  return pmb_critical_time_step(density, (bulk_modulus + 4 * shear_modulus / 3) / 1.8, horizon);
}

}  // namespace pd
