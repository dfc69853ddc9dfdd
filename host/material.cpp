#include "material.h"

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

}  // namespace pd
