// Energy accounting, once per frame (not a step kernel): per particle the kinetic energy, its
// share of the elastic strain energy and of the contact potential, its gravitational potential
// energy, and its ledger (work done on it, energy of its broken bonds). Summed over particles,
//   kinetic + strain + contact + gravity + released - work
// stays constant up to the integrator's error; a blow-up makes it grow without bound.
#pragma once

#include "cuda/kernels/collisions.h"
#include "cuda/kernels/springforces.h"
#include "cuda/kernels/state_based.h"

namespace pd {

struct Energy {
  double kinetic = 0, strain = 0, contact = 0, gravity = 0, work = 0, released = 0;

  PD_HD double mechanical() const { return kinetic + strain + contact + gravity; }
  // Constant for exact dynamics: mechanical energy plus what left, minus what came in.
  PD_HD double balance() const { return mechanical() + released - work; }
};

PD_HD inline Energy operator+(const Energy& a, const Energy& b) {
  Energy s;
  s.kinetic = a.kinetic + b.kinetic;
  s.strain = a.strain + b.strain;
  s.contact = a.contact + b.contact;
  s.gravity = a.gravity + b.gravity;
  s.work = a.work + b.work;
  s.released = a.released + b.released;
  return s;
}
PD_HD inline Energy& operator+=(Energy& a, const Energy& b) {
  return a = a + b;
}

// Strain energy of particle i: PMB sum_j c g_ij s^2 |xi| beta V_i V_j / 4; LPS
// V_i (K theta^2 / 2 + (15 mu / (2 m)) sum_j omega (e^d - e^p)^2 beta V_j).
PD_HD inline double strain_energy(int32_t i, const ParticlesView& p, const BondsView& b, const Material& m) {
  const real vol_i = p.volume(i);
  const bool state = m.model == kStateBased;
  const Vec4 si = state ? p.state[i] : Vec4{0, 0, 0, 0};
  double sum = 0;
  for_each_intact_bond(i, p, b, [&](int64_t slot, int32_t, const auto& g) {
    if (state) {
      const real ep = b.plastic ? b.plastic[slot] : real(0);
      sum += double(lps_bond_energy(g, si.x, si.y, ep, vol_i, m, surface_bond_at(b, slot)));
    } else {
      const real weight = pmb_bond_weight_at(g, m, b, slot);
      sum += double(pmb_bond_energy(g.e * g.inv_r0, g.r0, vol_i, weight, m));
    }
  });
  if (state) sum += 0.5 * double(m.bulk_modulus) * double(si.x) * double(si.x) * double(vol_i);
  return sum;
}

// Half of each contact pair's potential K_c (r_c - d)^3 / 3 (the integral of eq. 6), over the
// particle's contact list (valid for the current positions: the engine refreshes it first).
PD_HD inline double contact_energy(int32_t i, const ParticlesView& p, ContactView c, const MaterialTable& mt,
                                   real stiffness) {
  const Vec3 xi = p.position(i);
  const real quarter_i = contact_quarter(i, p, mt);
  double sum = 0;
  for (int32_t k = 0; k < c.count[i]; ++k) {
    const int32_t j = c.partner[c.slot(i, k)];
    const double rc = quarter_i + contact_quarter(j, p, mt);
    const double d = length(xi - p.position(j));
    if (d < rc) sum += stiffness * (rc - d) * (rc - d) * (rc - d) / 6.0;
  }
  return sum;
}

PD_HD inline Energy particle_energy(int32_t i, const ParticlesView& p, const BondsView& b, ContactView c,
                                    const MaterialTable& mt, const StepParams& sp, bool contact) {
  Energy e;
  const double mass = 1.0 / double(p.inv_mass[i]);
  const Vec3 v = p.vel[i];
  e.kinetic = 0.5 * mass * double(dot(v, v));
  // Relative to the rest configuration, from the displacement: float positions far from the
  // origin cannot resolve small sag.
  e.gravity = -mass * double(dot(sp.gravity, xyz(p.disp[i])));
  e.strain = strain_energy(i, p, b, mt.m[p.material[i]]);
  if (contact) e.contact = contact_energy(i, p, c, mt, sp.contact_stiffness);
  e.work = p.ledger[i].work;
  e.released = p.ledger[i].released;
  return e;
}

}  // namespace pd
