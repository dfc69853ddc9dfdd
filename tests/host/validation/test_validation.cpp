// Validation problems at coarse resolution (docs/validation.md has the references and the reasons
// for each tolerance). At these resolutions every particle of a bar or beam section lies within
// delta of a free surface, so the dominant error is the peridynamic surface effect, which is of
// order delta / W (W the width) and falls as the section is refined at fixed delta / lambda.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "host/validation/validation.h"

namespace pd {
namespace {

ValidationCase at(int resolution, std::optional<bool> surface_correction = std::nullopt) {
  ValidationCase c;
  c.resolution = resolution;
  c.surface_correction = surface_correction;
  return c;
}

const ValidationResult& figure(const std::vector<ValidationResult>& rs, const std::string& name) {
  for (const auto& r : rs)
    if (r.problem == name) return r;
  throw std::logic_error("no figure " + name);
}

void print(const std::vector<ValidationResult>& rs) {
  for (const auto& r : rs)
    std::printf("  %-30s measured %.5g reference %.5g error %.2f%% (%s)\n", r.problem.c_str(), r.measured,
                r.reference, 100 * r.rel_error, r.note.c_str());
}

// Bond-based bar without the surface correction: the error of E and nu against the continuum is
// bounded by the surface-layer ratio delta / W (0.75 at n = 4, 0.5 at n = 6) and falls with
// refinement; with an O(delta / W) error the 4 -> 6 step should shrink it by about 2/3, so it must
// at least shrink by 0.8.
TEST(Validation, TensionBarPmbConvergesToYoungsModulusAndQuarterPoisson) {
  const auto coarse = run_tension_bar_pmb(at(4, false)), fine = run_tension_bar_pmb(at(6, false));
  print(coarse);
  print(fine);
  for (const char* f : {"tension_bar_pmb/elongation", "tension_bar_pmb/poisson"}) {
    EXPECT_LT(figure(coarse, f).rel_error, 0.75) << f;
    EXPECT_LT(figure(fine, f).rel_error, 0.5) << f;
    EXPECT_LT(figure(fine, f).rel_error, 0.8 * figure(coarse, f).rel_error) << f;
  }
}

// With the surface correction (the default) the bar is within 3% of F L / (E A) at 8 particles
// across, the accuracy target of the correction (measured 2.5%; 18% without), and within 6% at 4
// across (measured 5.5%; 44% without). Its price is the lateral contraction: nu falls below 1/4
// as the factors across the surface grow (surface_correction.h): measured 0.234, 0.223, 0.230 at
// n = 4, 6, 8 (0.267 without at 8), so within 12% of 1/4 (the uncorrected bar's error at n = 6
// is 12.8%).
TEST(Validation, SurfaceCorrectedPmbBarIsWithinThreePercentAtEightAcross) {
  const auto coarse = run_tension_bar_pmb(at(4)), fine = run_tension_bar_pmb(at(8));
  print(coarse);
  print(fine);
  EXPECT_LT(figure(fine, "tension_bar_pmb/elongation").rel_error, 0.03);
  EXPECT_LT(figure(coarse, "tension_bar_pmb/elongation").rel_error, 0.06);
  for (const auto* r : {&coarse, &fine}) EXPECT_LT(figure(*r, "tension_bar_pmb/poisson").rel_error, 0.12);
}

// The state-based bar with the surface correction (opt-in for state-based materials): the factors
// make the cut families' second moments isotropic, so the dilatation of the near-surface layer
// stops over-counting the axial strain: at n = 8, nu within 0.01 of the input 0.3 (the issue's
// target; measured 0.2905, 0.323 without) and the elongation error at most 0.6 of the uncorrected
// one (measured 9.1% against 18.1%).
TEST(Validation, SurfaceCorrectedLpsBarHasTheInputPoissonRatio) {
  const auto on = run_tension_bar_lps(at(8, true)), off = run_tension_bar_lps(at(8));
  print(on);
  EXPECT_LT(std::fabs(figure(on, "tension_bar_lps/poisson").measured - 0.3), 0.01);
  EXPECT_LT(figure(on, "tension_bar_lps/elongation").rel_error,
            0.6 * figure(off, "tension_bar_lps/elongation").rel_error);
}

// Both tension bars `resolution` across on `particles`, with the ghost correction at its default
// dt / dt_c (state-based first), printed.
std::pair<std::vector<ValidationResult>, std::vector<ValidationResult>> ghost_corrected_bars(
    int resolution, const char* particles) {
  ValidationCase c = at(resolution, false);
  c.surface_ghosts = true;
  c.dt_fraction = kGhostDtFraction;
  c.particles = particles;
  auto lps = run_tension_bar_lps(c), pmb = run_tension_bar_pmb(c);
  print(lps);
  print(pmb);
  return {std::move(lps), std::move(pmb)};
}

// The ghost correction (issue 29; docs/validation.md): the bar 4 across, both models, at the
// lattice interior's own error (E +1.4% along an axis) within issue 29's 3% for 8 across, and
// nu within 0.01 of the input; the uncorrected LPS bar is 33% off there.
TEST(Validation, GhostCorrectedBarsAreAsStiffAsTheInterior) {
  const auto [lps, pmb] = ghost_corrected_bars(4, "grid");
  EXPECT_LT(figure(lps, "tension_bar_lps/elongation").rel_error, 0.03);
  EXPECT_LT(std::fabs(figure(lps, "tension_bar_lps/poisson").measured - 0.3), 0.01);
  EXPECT_LT(figure(pmb, "tension_bar_pmb/elongation").rel_error, 0.03);
  EXPECT_LT(std::fabs(figure(pmb, "tension_bar_pmb/poisson").measured - 0.25), 0.01);
}

// Scattered particles (issue 29: "tets and Voronoi bodies get the correction too"): the same
// bar filled with Voronoi cells, 6 across, meets the targets for 8 across with ghosts
// (elongation within 3%, the state-based nu within 0.01); uncorrected, the state-based bar is 20%
// off (docs/validation.md, scattered particles).
TEST(Validation, GhostCorrectedVoronoiBarsMeetTheTargets) {
  const auto [lps, pmb] = ghost_corrected_bars(6, "voronoi");
  EXPECT_LT(figure(lps, "tension_bar_lps_voronoi/elongation").rel_error, 0.03);
  EXPECT_LT(std::fabs(figure(lps, "tension_bar_lps_voronoi/poisson").measured - 0.3), 0.01);
  EXPECT_LT(figure(pmb, "tension_bar_pmb_voronoi/elongation").rel_error, 0.03);
}

// Tets, at the horizon of 4 lambda the vase takes: the ghost set-up asks the tets' own solid which
// stencil points lie outside the body. The state-based bar 4 across comes out 5.8% stiff (9.5% when
// a stencil point far from every tet centroid counted as outside, which put ghosts inside the
// body), and 2.4% at 8 across, issue 29's target (measured on the GPU; docs/validation.md).
TEST(Validation, GhostCorrectedTetBarTakesGhostsOutsideItsSolid) {
  ValidationCase c = at(4, false);
  c.delta_over_lambda = 4;
  c.surface_ghosts = true;
  c.dt_fraction = kGhostDtFraction;
  c.particles = "tets";
  const auto lps = run_tension_bar_lps(c);
  print(lps);
  EXPECT_LT(figure(lps, "tension_bar_lps_tets/elongation").rel_error, 0.065);
  EXPECT_LT(std::fabs(figure(lps, "tension_bar_lps_tets/poisson").measured - 0.3), 0.025);
}

// State-based bar: same bounds; nu converges to the input 0.3, not to PMB's 1/4.
TEST(Validation, TensionBarLpsConvergesToInputPoisson) {
  const auto coarse = run_tension_bar_lps(at(4)), fine = run_tension_bar_lps(at(6));
  print(coarse);
  print(fine);
  for (const char* f : {"tension_bar_lps/elongation", "tension_bar_lps/poisson"}) {
    EXPECT_LT(figure(coarse, f).rel_error, 0.75) << f;
    EXPECT_LT(figure(fine, f).rel_error, 0.5) << f;
    EXPECT_LT(figure(fine, f).rel_error, 0.8 * figure(coarse, f).rel_error) << f;
  }
  EXPECT_LT(std::fabs(figure(fine, "tension_bar_lps/poisson").measured - 0.3),
            std::fabs(figure(fine, "tension_bar_lps/poisson").measured - 0.25));
}

// The wave front runs at the bar velocity of the discrete bar: sqrt(E_eff / rho) with E_eff the
// modulus the static tension test measures at the same resolution. Tolerance 1.5%: the front is
// located to ~lambda/20 per sample over 14 widths of travel, and the one-third level of the
// Airy head reaches c0 t only asymptotically (an offset growing as t^(1/3)). Against the
// continuum sqrt(E/rho) the error is the surface effect's: below delta / (2W) (half the
// modulus bound, as c ~ sqrt(E)), and falling with refinement.
TEST(Validation, WaveFrontRunsAtTheBarVelocity) {
  for (int n : {4, 6}) {
    const auto wave = run_wave_bar(at(n));
    const auto bar = run_tension_bar_pmb(at(n));
    print(wave);
    const double e_eff = figure(bar, "tension_bar_pmb/elongation").reference /
                         figure(bar, "tension_bar_pmb/elongation").measured * 72e9;
    const double c_eff = std::sqrt(e_eff / 2440);
    std::printf("  n = %d: sqrt(E_eff / rho) = %.1f m/s\n", n, c_eff);
    EXPECT_NEAR(wave[0].measured / c_eff, 1.0, 0.015);
    EXPECT_LT(wave[0].rel_error, 3.0 / (2.0 * n));
  }
  EXPECT_LT(run_wave_bar(at(6))[0].rel_error, 0.8 * run_wave_bar(at(4))[0].rel_error);
}

// State-based cantilever: on a flat face the LPS energy of a particle equals the bulk one under
// homogeneous strain (a half-sphere family's second moment stays isotropic), so the beam's skin,
// which carries the bending, keeps its stiffness; the errors left come from the edges (quarter
// families) and from particles within delta of a face, which stiffen (the tension bar shows it).
// Measured (bench/accuracy): 1.2% at n = 4, 6.5% (stiffer) at n = 6, 0.5% at n = 6 with
// delta = 4 lambda: not monotone in n, so this is a band, not a convergence claim. Tolerance 5%
// at n = 4: the lattice error of E at delta = 3 lambda (+1.5%, DESIGN.md) plus the edge share of
// the second moment of area (the 4 corner columns of 16 carry 1/4 of I) at the tension bar's
// edge-dominated stiffening of ~10%, plus < 1% from the one-period mean of the swing.
TEST(Validation, StateBasedCantileverMatchesTimoshenko) {
  const auto r = run_cantilever_lps(at(4));
  print(r);
  EXPECT_LT(r[0].rel_error, 0.05);
}

// Twisted square bar (Chen's twisting bar, in the small-strain range where Saint-Venant's
// solution holds): the torsional stiffness carries the same O(delta / W) surface error as the
// tension bar (the shear stress of torsion is largest at the surface), so the same bounds apply:
// below delta / W and shrinking by at least 0.8x from n = 4 to 6. Measured (CPU, float): 11.7% at
// n = 4, 1.3% at n = 6.
TEST(Validation, TwistedBarMatchesSaintVenantTorsion) {
  const auto coarse = run_bar_twist_lps(at(4)), fine = run_bar_twist_lps(at(6));
  print(coarse);
  print(fine);
  const char* f = "bar_twist_lps/twist_angle";
  EXPECT_LT(figure(coarse, f).rel_error, 0.75);
  EXPECT_LT(figure(fine, f).rel_error, 0.5);
  EXPECT_LT(figure(fine, f).rel_error, 0.8 * figure(coarse, f).rel_error);
}

// Free bar spinning one and a half turns (Chen's swinging bar: no ghost forces under large
// rotation). Pair forces along the bonds conserve angular momentum, so it may drift by float
// round-off only (1e-5 over ~16,000 steps). The centrifugal stretch must be what the static bar's
// modulus at the same resolution predicts: the rotation adds no strain of its own. Tolerance 5%:
// the tension test measures E over a central gauge while the spin stretch integrates over the
// whole bar, ends within delta of a free face included (measured: 1.9% apart at n = 4).
TEST(Validation, SpinningBarStretchesOnlyByTheCentrifugalLoad) {
  const auto spin = run_bar_spin_lps(at(4)), bar = run_tension_bar_lps(at(4));
  print(spin);
  const auto tension = figure(bar, "tension_bar_lps/elongation");
  const double e_ratio = tension.measured / tension.reference;  // E / E_eff
  const auto stretch = figure(spin, "bar_spin_lps/stretch");
  std::printf("  stretch predicted by E_eff: %.5g\n", stretch.reference * e_ratio);
  EXPECT_NEAR(stretch.measured / (stretch.reference * e_ratio), 1.0, 0.05);
  EXPECT_NEAR(figure(spin, "bar_spin_lps/angular_momentum").measured, 1.0, 1e-5);
}

// Crack in the pre-notched glass plate at 20 particles across (delta = 6 mm): the crack runs
// from the notch, stays mirror-symmetric (no scatter; the set-up is symmetric), and its tip
// stays below the Rayleigh speed. Branching needs a finer plate: benchmark only.
TEST(Validation, NotchedPlateCrackIsSymmetricAndSubRayleigh) {
  const auto r = run_crack_branching(at(20));
  print(r);
  const double speed = figure(r, "crack_branching/crack_speed").measured;
  const double rayleigh = 0.9194 * std::sqrt(72e9 / 2.5 / 2440);
  EXPECT_GT(speed, 0.1 * rayleigh);  // it ran
  EXPECT_LT(speed, rayleigh);
  EXPECT_GT(figure(r, "crack_branching/symmetry").measured, 0.95);
}

// Another traction (`perifrac validate --traction`) is what loads the plate: at 2.5 MPa, 0.41 E
// s0 at delta = 6 mm (the default 3.04 MPa is 0.49 there), the crack still runs from the notch,
// symmetric and below the Rayleigh speed, and the run reports the traction it applied.
TEST(Validation, NotchedPlateTakesAFixedTraction) {
  ValidationCase c = at(20);
  c.traction = 2.5e6;
  const auto r = run_crack_branching(c);
  print(r);
  const double speed = figure(r, "crack_branching/crack_speed").measured;
  const double rayleigh = 0.9194 * std::sqrt(72e9 / 2.5 / 2440);
  EXPECT_GT(speed, 0.1 * rayleigh);
  EXPECT_LT(speed, rayleigh);
  EXPECT_GT(figure(r, "crack_branching/symmetry").measured, 0.95);
  EXPECT_NE(r[0].note.find("traction 2.5 MPa"), std::string::npos) << r[0].note;
}

// The sanitizers run the code 4-5 times slower: the two fracture problems below (130-140 s each
// on two cores) then run at a coarse size, for the memory checks alone.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

// The double-edge-notched bar at 20 across (a / delta = 1.7) breaks within issue 29's 10% of
// LEFM's sigma_f = K_Ic / (sqrt(pi a) F(a/b)) with the surface correction (measured -6.0%; -1.7%
// and +2.8% at 40 and 80 across on the GPU). The peak is the ligament's: the run stops when the
// reaction turns compressive as the severed halves ring (their crests, up to 1.38 sigma_f, were
// once read as the failure stress). Every bond across the ligament broke, so the released energy
// is at least G0 per ligament area (measured 4.85 J/m^2: bonds broken off the plane add).
TEST(Validation, NotchedBarBreaksAtTheLefmStress) {
  if (kSanitized) {  // the same code at a coarse size; the figures are checked in the release suite
    const auto r = run_notched_bar_pmb(at(10));
    EXPECT_GT(figure(r, "notched_bar_pmb/failure_stress").measured, 0);
    EXPECT_GT(figure(r, "notched_bar_pmb/released_energy").measured, 0);
    return;
  }
  const auto r = run_notched_bar_pmb(at(20));
  print(r);
  EXPECT_LT(figure(r, "notched_bar_pmb/failure_stress").rel_error, 0.10);
  const auto energy = figure(r, "notched_bar_pmb/released_energy");
  EXPECT_GT(energy.measured, energy.reference);
}

// A sharp crack under Williams' K field grows by delta at Griffith's K_Ic = sqrt(E G0) within the
// finite field's error, which falls with delta / R (measured +11.3, +9.3, +7.8, +6.7% at R = 10,
// 20, 30, 40 delta): at R = 10 delta within 15%, and not before K_Ic (a crack growing earlier
// would take less than G0 per area).
TEST(Validation, CrackTipGrowsAtGriffithsToughness) {
  if (kSanitized) {
    EXPECT_GT(figure(run_crack_tip_pmb(at(12)), "crack_tip_pmb/growth_toughness").measured, 0);
    return;
  }
  const auto r = run_crack_tip_pmb(at(30));
  print(r);
  const auto growth = figure(r, "crack_tip_pmb/growth_toughness");
  EXPECT_GT(growth.measured, growth.reference);
  EXPECT_LT(growth.measured, 1.15 * growth.reference);
}

}  // namespace
}  // namespace pd
