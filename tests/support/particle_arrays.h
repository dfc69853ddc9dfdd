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
    p.rest = rest.data();
    p.disp = disp.data();
    p.vel = vel.data();
    p.force = force.data();
    p.inv_mass = inv_mass.data();
    p.material = material.data();
    p.body = body.data();
    p.flags = flags.data();
    p.strain_limit0 = tau0.data();
    p.strain_min = smin.data();
    p.intact = intact.data();
    p.state = state.data();
    p.ledger = ledger.data();
    return p;
  }
};

}  // namespace pd::testing
