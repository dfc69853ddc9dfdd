// Engine::read_frame against reads made at once: frames taken every `every` steps and finished
// only after the engine stepped on (more frames out than the read slots, so some are read at once)
// must give, bit for bit, the state and the bond changes that read_state and bond_changes give a
// twin engine at the same steps. Both engines from `make`, which must be deterministic.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "cuda/engine/engine.h"
#include "tests/support/same_state.h"

namespace pd::testing {

inline void expect_frames_read_later_as_read_at_once(const std::function<std::unique_ptr<Engine>()>& make,
                                                     int frames, int64_t every) {
  auto later = make(), now = make();
  BondChanges built_later, built_now;
  later->bond_changes(std::numeric_limits<size_t>::max(), built_later);
  now->bond_changes(std::numeric_limits<size_t>::max(), built_now);
  BondLists bonds_later = built_later.bonds, bonds_now = built_now.bonds;
  const size_t slots = bonds_later.neighbor.size();

  std::vector<std::unique_ptr<FrameRead>> reads;
  std::vector<ParticleState> states(static_cast<size_t>(frames));
  std::vector<BondLists> bonds(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    later->advance(every);
    now->advance(every);
    reads.push_back(later->read_frame(slots, f > 0));
    now->read_state(states[size_t(f)]);
    if (f > 0) now->update_bonds(bonds_now);
    bonds[size_t(f)] = bonds_now;
  }
  later->advance(every);  // (the last frame's copies may still be on their way)
  ASSERT_GT(now->broken_bonds(), 0) << "the run must break bonds between frames";
  for (int f = 0; f < frames; ++f) {
    ParticleState s;
    BondChanges changes;
    reads[size_t(f)]->finish(s, changes);
    reads[size_t(f)].reset();
    expect_same_particles(s, states[size_t(f)]);
    EXPECT_EQ(s.intact, states[size_t(f)].intact) << "frame " << f;
    if (f == 0) continue;
    ASSERT_FALSE(changes.whole) << "frame " << f;
    changes.apply_to(bonds_later);
    ASSERT_EQ(bonds_later.neighbor, bonds[size_t(f)].neighbor) << "frame " << f;
  }
}

}  // namespace pd::testing
