#include <cmath>

#include "host/validation/validation.h"

namespace pd {

ValidationResult make_result(std::string problem, double measured, double reference) {
  ValidationResult r;
  r.problem = std::move(problem);
  r.measured = measured;
  r.reference = reference;
  r.rel_error = std::fabs(measured - reference) / std::fabs(reference);
  return r;
}

// Resolutions: particles across the bar or beam width, the plate height, or the disc's radius.
const std::vector<ValidationProblem>& validation_problems() {
  static const std::vector<ValidationProblem> problems = {
      {"wave_bar", "step wave in a PMB bar: front speed against sqrt(E/rho)", {4, 6, 8, 12}, run_wave_bar},
      {"tension_bar_pmb",
       "PMB tension bar: elongation FL/(EA), Poisson ratio 1/4",
       {4, 6, 8, 12},
       run_tension_bar_pmb,
       true},
      {"tension_bar_lps",
       "state-based tension bar: elongation FL/(EA), Poisson ratio 0.3",
       {4, 6, 8, 12},
       run_tension_bar_lps,
       true},
      {"cantilever_pmb",
       "PMB cantilever under its weight: tip deflection (Timoshenko)",
       {4, 6, 8},
       run_cantilever_pmb},
      {"cantilever_lps",
       "state-based cantilever under its weight: tip deflection (Timoshenko)",
       {4, 6, 8},
       run_cantilever_lps},
      {"bar_twist_lps",
       "state-based square bar in torsion: twist angle (Saint-Venant, Chen's twisting bar)",
       {4, 6, 8},
       run_bar_twist_lps},
      {"bar_spin_lps",
       "state-based free bar spinning 1.5 turns: centrifugal stretch, angular momentum (Chen's swinging bar)",
       {4, 6, 8},
       run_bar_spin_lps},
      {"crack_branching",
       "pre-notched glass plate: crack speed, branches, symmetry",
       {20, 40, 80},
       run_crack_branching},
      {"notched_bar_pmb",
       "double-edge-notched glass bar pulled to failure: failure stress against LEFM (K_Ic = sqrt(E G0))",
       {10, 20, 30},
       run_notched_bar_pmb},
      {"crack_tip_pmb",
       "sharp crack in a PMB disc under Williams' K field: K at growth against sqrt(E G0)",
       {30, 60},
       run_crack_tip_pmb},
  };
  return problems;
}

}  // namespace pd
