// Runs compared bit for bit (expect_same_run), and runs of one input with `springforces` screened
// in every pass, never, and as the engine chooses (cuda/kernels/bond_screen.h); shared by the CPU
// and GPU suites.
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

// Two runs at the same step with the same bits: state, bonds, energy ledger and plastic history.
inline void expect_same_run(Engine& a, Engine& b) {
  ParticleState sa, sb;
  BondLists ba, bb;
  EngineSnapshot pa, pb;
  a.read_state(sa);
  b.read_state(sb);
  a.read_bonds(ba);
  b.read_bonds(bb);
  a.save(pa);
  b.save(pb);
  EXPECT_EQ(a.step(), b.step());
  EXPECT_EQ(a.time(), b.time());
  EXPECT_TRUE(same_bits(pa.disp, pb.disp));
  EXPECT_TRUE(same_bits(sa.vel, sb.vel));
  EXPECT_TRUE(same_bits(sa.force, sb.force));
  EXPECT_EQ(sa.intact, sb.intact);
  EXPECT_EQ(ba.neighbor, bb.neighbor);
  EXPECT_TRUE(same_bits(pa.strain_min, pb.strain_min));
  EXPECT_TRUE(same_bits(pa.ledger, pb.ledger));
  EXPECT_TRUE(same_bits(pa.state, pb.state));
  EXPECT_TRUE(same_bits(pa.plastic, pb.plastic));
}

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
  for (int r = 1; r < 3; ++r) {
    SCOPED_TRACE(r == 1 ? "screened in every pass" : "screened as the engine chooses");
    expect_same_run(*runs[0], *runs[r]);
  }
}

}  // namespace pd::testing
