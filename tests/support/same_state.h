// Bit-for-bit comparison of two engines' particle states (Engine::read_state): displacements,
// velocities and forces, every component.
#pragma once

#include <gtest/gtest.h>

#include "cuda/engine/engine.h"

namespace pd::testing {

inline void expect_same_particles(const ParticleState& a, const ParticleState& b) {
  ASSERT_EQ(a.disp.size(), b.disp.size());
  const auto same = [](Vec3 x, Vec3 y) { return x.x == y.x && x.y == y.y && x.z == y.z; };
  for (size_t i = 0; i < a.disp.size(); ++i) {
    ASSERT_TRUE(same(a.disp[i], b.disp[i])) << "displacement of " << i;
    ASSERT_TRUE(same(a.vel[i], b.vel[i])) << "velocity of " << i;
    ASSERT_TRUE(same(a.force[i], b.force[i])) << "force of " << i;
  }
}

}  // namespace pd::testing
