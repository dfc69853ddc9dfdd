// Runs of one input with `springforces` screened in every pass, never, and as the engine
// chooses (cuda/kernels/bond_screen.h), compared bit for bit; shared by the CPU and GPU suites.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <memory>
#include <vector>

#include "cuda/engine/engine.h"

namespace pd::testing {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

using EngineFactory = std::function<std::unique_ptr<Engine>(const SimulationInput&)>;

// The three runs of `in` over `steps` steps leave the same state, bonds and energy ledger bits;
// the run must break bonds, and the automatic choice must use both forms.
inline void expect_screen_modes_agree(const EngineFactory& make, SimulationInput in, int64_t steps) {
  std::unique_ptr<Engine> runs[3];
  const BondScreen modes[3] = {BondScreen::kOff, BondScreen::kAlways, BondScreen::kAuto};
  for (int r = 0; r < 3; ++r) {
    in.screen = modes[r];
    runs[r] = make(in);
    runs[r]->advance(steps);
  }
  const int64_t passes = runs[0]->force_passes();
  ASSERT_EQ(passes, steps + 1);  // one at set-up
  EXPECT_EQ(runs[0]->screened_passes(), 0);
  EXPECT_EQ(runs[1]->screened_passes(), passes);
  EXPECT_GT(runs[2]->screened_passes(), 0) << "auto: screened before the first break";
  EXPECT_LT(runs[2]->screened_passes(), passes) << "auto: the breaking pass after a break";
  ASSERT_GT(runs[0]->broken_bonds(), 0) << "the run must break bonds";
  ParticleState base;
  BondLists base_bonds;
  EngineSnapshot base_snapshot;
  runs[0]->read_state(base);
  runs[0]->read_bonds(base_bonds);
  runs[0]->save(base_snapshot);
  for (int r = 1; r < 3; ++r) {
    SCOPED_TRACE(r == 1 ? "screened in every pass" : "screened as the engine chooses");
    ParticleState s;
    BondLists b;
    EngineSnapshot snapshot;
    runs[r]->read_state(s);
    runs[r]->read_bonds(b);
    runs[r]->save(snapshot);
    EXPECT_TRUE(same_bits(snapshot.disp, base_snapshot.disp));
    EXPECT_TRUE(same_bits(s.vel, base.vel));
    EXPECT_TRUE(same_bits(s.force, base.force));
    EXPECT_EQ(s.intact, base.intact);
    EXPECT_EQ(b.neighbor, base_bonds.neighbor);
    EXPECT_TRUE(same_bits(snapshot.strain_min, base_snapshot.strain_min));
    EXPECT_TRUE(same_bits(snapshot.ledger, base_snapshot.ledger));
    EXPECT_TRUE(same_bits(snapshot.state, base_snapshot.state));
    EXPECT_TRUE(same_bits(snapshot.plastic, base_snapshot.plastic));
  }
}

}  // namespace pd::testing
