// Bond-based (PMB) material constants from engineering inputs, with their sources.
#pragma once

#include "cuda/views.h"

namespace pd {

// Micromodulus of the 3D prototype microelastic brittle model: c = 18 K / (pi delta^4),
// force per unit volume squared per unit stretch (Silling & Askari 2005, eq. 15).
double pmb_micromodulus(double bulk_modulus, double horizon);

// Sums over the family of a particle deep inside a simple-cubic lattice of spacing lambda (the
// bonds the family builder makes: |xi| <= the family radius, kHorizonSlack included), each bond
// counting with its partial-volume fraction beta (volume_fraction) and V_j = lambda^3:
//   bond_sum     = sum_j |xi| beta V_j, whose continuum value is pi delta^4;
//   crossing_sum = sum over the bonds with xi_z > 0 of xi_z |xi| beta / lambda^3 times V_i V_j
//                  (the bonds that cross a lattice plane, per unit area, weighted by length),
//                  whose continuum value is pi delta^5 / 5;
//   axial_sum    = sum_j n_x^4 |xi| beta V_j (n = xi / |xi|), the uniaxial strain's sum along x
//                  (the same along y and z), whose continuum value is pi delta^4 / 5.
struct LatticeFamilySums {
  double bond_sum = 0, crossing_sum = 0, axial_sum = 0;
};
LatticeFamilySums lattice_family_sums(const Material& m);

// The PMB micromodulus that gives the bulk modulus K exactly to an interior particle of the
// lattice: c = 18 K / bond_sum (pmb_micromodulus with the lattice sum in place of pi delta^4).
double pmb_lattice_micromodulus(double bulk_modulus, const Material& m);

// The PMB critical stretch whose broken bonds across a lattice plane release the fracture
// energy G0 per unit area: G0 = c s0^2 crossing_sum / 2. Its continuum limit is Silling &
// Askari's (2005, eq. 21) s0 = sqrt(5 G0 / (9 K delta)); Levine et al. 2014 print
// sqrt(5G/(K delta)), three times larger.
double pmb_lattice_critical_stretch(double fracture_energy, double micromodulus, const Material& m);

// Critical time step of an explicit PMB integration (Silling & Askari 2005, eq. 29) for a
// particle with the continuum family sum_j V_j c/|xi_j| ~ c 2 pi delta^2 = 36 K / delta^2:
// dt_c = sqrt(2 rho delta^2 / (36 K)).
double pmb_critical_time_step(double density, double bulk_modulus, double horizon);

// Critical stretch of the ordinary state-based solid from fracture energy (Madenci &
// Oterkus 2014, eq. 5.20 in 3D): s0 = sqrt(G0 / ((3 mu + (3/4)^4 (K - 5 mu / 3)) delta)).
double lps_critical_stretch(double fracture_energy, double bulk_modulus, double shear_modulus,
                            double horizon);

// Mitchell's yield constant from a von Mises yield stress, 3D: psi_0 = 25 sigma_Y^2 / (8 pi delta^5)
// (Mitchell 2011; the constant Peridigm and LAMMPS use).
double yield_psi0(double yield_stress, double horizon);

// Stable time step of the state-based solid, estimated as that of a PMB material with the
// same P-wave modulus (PMB has K + 4 mu / 3 = 1.8 K): the PMB formula with K = (K + 4 mu / 3) / 1.8.
double lps_critical_time_step(double density, double bulk_modulus, double shear_modulus, double horizon);

}  // namespace pd
