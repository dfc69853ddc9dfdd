// The energy watchdog: a balance that grows past the energy the run started with and exchanged
// is a blow-up, however large the grown kinetic energy itself is; ordinary drift is not.
#include "host/app/energy_watch.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pd {
namespace {

TEST(EnergyWatch, RunawayKineticEnergyIsABlowUp) {
  Energy e0;
  e0.kinetic = 10;
  Energy e = e0;
  e.kinetic = 1e6;  // the scale must not contain the grown energy (it would cap the ratio at 1)
  EXPECT_GT(energy_excess(e0, e), 1e4);
}

TEST(EnergyWatch, BookedWorkAndDriftAreNot) {
  Energy e0;
  e0.kinetic = 10;
  Energy e;
  e.kinetic = 70;
  e.strain = 45;
  e.work = 100;  // a projectile did 100 J of work: the balance stays 10 + 5 J of drift
  EXPECT_NEAR(energy_excess(e0, e), 5.0 / 110.0, 1e-12);
  Energy falling;  // energy from gravity: kinetic gained, potential lost
  falling.gravity = -50;
  falling.kinetic = 50.5;
  EXPECT_LT(energy_excess(Energy(), falling), 0.02);
}

TEST(EnergyWatch, EnergyFromNothingIsABlowUp) {
  Energy e;
  e.kinetic = 1e-3;
  EXPECT_TRUE(std::isinf(energy_excess(Energy(), e)));
  EXPECT_EQ(energy_excess(Energy(), Energy()), 0);
}

}  // namespace
}  // namespace pd
