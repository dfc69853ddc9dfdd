// Every per-particle array a kernel body reads, held in vectors, and the view of them: for
// kernel tests that build their particles by hand.
#pragma once

#include <vector>

#include "cuda/views.h"

namespace pd::testing {

struct ParticleArrays {
  std::vector<Vec4> rest, disp, state;  // (X, V), (u, tau'), (theta, 1/m, phi, -)
  std::vector<Vec3> vel, force;
  std::vector<real> inv_mass, tau0, smin;
  std::vector<uint16_t> material;
  std::vector<int32_t> body, intact;
  std::vector<uint8_t> flags;
  std::vector<Ledger> ledger;
  int32_t broke = 0;  // the flag a force pass raises where a bond broke (kernels/bond_screen.h)

  ParticlesView view() {
    ParticlesView p;
    p.n = int32_t(rest.size());
    p.rest = view_of(rest);
    p.disp = view_of(disp);
    p.vel = view_of(vel);
    p.force = view_of(force);
    p.inv_mass = view_of(inv_mass);
    p.material = view_of(material);
    p.body = view_of(body);
    p.flags = view_of(flags);
    p.strain_limit0 = view_of(tau0);
    p.strain_min = view_of(smin);
    p.intact = view_of(intact);
    p.state = view_of(state);
    p.ledger = view_of(ledger);
    return p;
  }
};

}  // namespace pd::testing
