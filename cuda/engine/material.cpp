#include "cuda/engine/material.h"

#include <cmath>

namespace pd {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double pmb_micromodulus(double bulk_modulus, double horizon) {
  return 18.0 * bulk_modulus / (kPi * std::pow(horizon, 4));
}

double pmb_critical_stretch(double fracture_energy, double bulk_modulus, double horizon) {
  return std::sqrt(5.0 * fracture_energy / (9.0 * bulk_modulus * horizon));
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
