#include "cuda/engine/engine.h"

#include <utility>

namespace pd {

const char* backend_name(Backend b) {
  return b == Backend::kCuda ? "cuda" : "cpu";
}

namespace {

// A frame read when it is taken (Engine::read_frame's default: a partitioned run gathers its
// ranks' state then).
class FrameReadNow final : public FrameRead {
 public:
  FrameReadNow(Engine& engine, size_t slots, bool changes) {
    engine.read_state(state_);
    if (changes) engine.bond_changes(slots, changes_);
  }
  void finish(ParticleState& state, BondChanges& changes) override {
    std::swap(state, state_);
    std::swap(changes, changes_);
  }

 private:
  ParticleState state_;
  BondChanges changes_;
};

}  // namespace

std::unique_ptr<FrameRead> Engine::read_frame(size_t slots, bool changes) {
  return std::make_unique<FrameReadNow>(*this, slots, changes);
}

std::unique_ptr<Engine> make_engine(Backend b, const SimulationInput& in) {
  return b == Backend::kCuda ? make_cuda_engine(in) : make_cpu_engine(in);
}

}  // namespace pd
