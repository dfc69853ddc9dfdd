// The simulation engine seen from the host: one interface, two backends that run the same
// kernel bodies (cuda/engine_impl.h). Host code never touches device memory directly.
#pragma once

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "cuda/engine/particle_set.h"
#include "cuda/kernel_stats.h"
#include "cuda/kernels/energy.h"

namespace pd {

enum class Backend { kCpu, kCuda };

const char* backend_name(Backend b);

// Bonds (stored per direction) that the scene's cracks removed or weakened (host/bond_cuts.h).
struct BondCutCounts {
  int64_t removed = 0, weakened = 0;
};

struct FamilyStats {
  int64_t bonds = 0;  // stored bonds, each pair counted once per direction
  int32_t min = 0, max = 0;
  double mean = 0;
  int64_t slots = 0;              // sliced-ELL storage, padding included
  int64_t lattice_particles = 0;  // particles with lattice families (lattice_families.h)
  int64_t lattice_listed = 0;  // of them, those reading partners from their lists (a rank's, Stencil::listed)
  int64_t surface_rows = 0;    // rows of surface-corrected lattice bond factors (SurfaceRows)
  BondCutCounts cuts;
};

// Per-particle state copied back to the host every frame: the state table's fields with a frame
// role (cuda/state_fields.h), named as there: disp (u, without tau'), vel, force, intact.
struct ParticleState {
#define PD_FRAME_MEMBER(name, Type, length, when, saved, halo, frame) \
  PD_IF_FRAME(frame, std::vector<PD_FRAME_TYPE(frame, Type)> name;)
  PD_PARTICLE_FIELDS(PD_FRAME_MEMBER)
#undef PD_FRAME_MEMBER
};

// One frame field as the engine stores it (EngineState::frame_fields): `count` elements of `bytes`.
struct FrameField {
  const void* data = nullptr;
  size_t count = 0, bytes = 0;
};

// f(member, xyz) for each field of a ParticleState, in the state table's order; `xyz`
// (std::true_type) where the member is the xyz part of a stored Vec4.
template <class F>
void for_each_frame_member(ParticleState& s, F f) {
#define PD_FRAME_VISIT(name, Type, length, when, saved, halo, frame) \
  PD_IF_FRAME(frame, f(s.name, std::bool_constant<frame == kFrameXyz>{});)
  PD_PARTICLE_FIELDS(PD_FRAME_VISIT)
#undef PD_FRAME_VISIT
}

// Families as stored (sliced ELL, see BondsView), copied back to the host.
struct SurfaceGhostCounts {
  int64_t ghosted = 0, thin = 0, precracked = 0;
  int64_t linear = 0;  // of the ghosted, those on the linear fit
};

struct BondLists {
  std::vector<int64_t> slice_offset;
  std::vector<int32_t> count;
  std::vector<int32_t> neighbor;
  BondsView view() const {
    BondsView v;
    v.n = int32_t(count.size());
    v.slice_offset = view_of(slice_offset);
    v.count = view_of(count);
    v.neighbor = {const_cast<int32_t*>(neighbor.data()), int64_t(neighbor.size())};
    return v;
  }
};

// What changed in an engine's bonds since a reader's previous look (Engine::bond_changes): the
// bonds whole, or the slots whose neighbour index flipped between j and ~j (broken, or whole again
// after a restore), slot s as bit s % 32 of word s / 32.
struct BondChanges {
  bool whole = true;
  BondLists bonds;                // when whole
  std::vector<uint32_t> flipped;  // when not
  // Brings `into`, the reader's bonds as of its previous look, up to date (the whole bonds moved).
  void apply_to(BondLists& into) {
    if (whole) {
      into = std::move(bonds);
      return;
    }
    for (size_t w = 0; w < flipped.size(); ++w)
      for (uint32_t c = flipped[w]; c != 0; c &= c - 1) {
        int32_t& j = into.neighbor[32 * w + size_t(__builtin_ctz(c))];
        j = ~j;
      }
  }
};

// A frame taken at one step and read back while the engine steps on (Engine::read_frame): finish()
// waits for the copies and gives what read_state and bond_changes would have given at that step.
class FrameRead {
 public:
  virtual ~FrameRead() = default;
  // Fills `state` (its vectors' memory kept where their sizes hold) and, when the frame was taken
  // with its bond changes, `changes`. Any thread; once.
  virtual void finish(ParticleState& state, BondChanges& changes) = 0;
};

// Everything a run changes, for checkpoints: the state table's saved fields (cuda/state_fields.h)
// as host vectors, named as there. Restoring it into an engine built from the same input
// continues the run bit for bit on the same backend; the rest (reference positions, masses,
// strain limits, families as built) follows from the input. Fields a run does not have (state
// of a bond-based run, plastic of an elastic one) are empty.
struct EngineSnapshot {
  int64_t step = 0;
  double time = 0;
#define PD_SNAPSHOT_MEMBER(name, Type, length, when, saved, ...) \
  PD_IF_SAVED(saved, std::vector<std::remove_const_t<Type>> name;)
  PD_STATE_FIELDS(PD_SNAPSHOT_MEMBER)
#undef PD_SNAPSHOT_MEMBER
  std::vector<double> free_bodies;  // the free colliders' state (FreeBodies::saved)
};

// f(name, vector) for every field of a snapshot, in the table's order (checkpoint files).
template <class Snapshot, class F>
void for_each_snapshot_field(Snapshot& s, F f) {
#define PD_SNAPSHOT_VISIT(name, Type, length, when, saved, ...) PD_IF_SAVED(saved, f(#name, s.name);)
  PD_STATE_FIELDS(PD_SNAPSHOT_VISIT)
#undef PD_SNAPSHOT_VISIT
}

// One rank of a partitioned run (cuda/parallel/), counted since its set-up: what it holds and
// where its step time went.
struct RankStats {
  int64_t particles = 0;    // its own
  int64_t ghosts = 0;       // bond and contact ghosts it holds now
  int64_t bonds = 0;        // its own particles' bonds as built
  double step_seconds = 0;  // wall time in `advance`, exchanges included
  double halo_seconds = 0;  // of which exchanging ghosts
  int64_t halo_bytes = 0;   // sent to other ranks
  int64_t halo_exchanges = 0;
  int64_t interior = 0;          // own particles that read no ghost
  char halo_transport[24] = {};  // "nccl", "mpi via host memory" or "mpi"
  int32_t overlapped = 0;        // 1: interior forces computed while the halo travels
};

// One stage of an engine's set-up and its wall time, the device's work in it included.
struct SetupStage {
  std::string name;
  double seconds = 0;
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual Backend backend() const = 0;
  virtual std::string device_name() const = 0;
  virtual const FamilyStats& family_stats() const = 0;
  // Advances `steps` velocity-Verlet steps of the fixed dt.
  virtual void advance(int64_t steps) = 0;
  virtual int64_t step() const = 0;
  virtual double time() const = 0;
  virtual void read_state(ParticleState& out) = 0;
  virtual void read_bonds(BondLists& out) = 0;
  // What changed since the previous call, for a reader whose bonds have `slots` slots: the first
  // call (or one whose slots are not the engine's, e.g. SIZE_MAX) gives the bonds whole, later ones
  // only which slots flipped (one bit per slot), which is what a frame's output needs.
  virtual void bond_changes(size_t slots, BondChanges& out) {
    (void)slots;
    out.whole = true;
    read_bonds(out.bonds);
  }
  // The frame at the current step: the state as read_state gives it and, with `changes`, the
  // bonds' changes as bond_changes(slots) gives them, copied back beside the steps that follow.
  // The engine may step on at once; only finish() waits. Read in order: a frame's changes are
  // since the frame read before it. (This one reads at once; the backends' engines copy into
  // page-locked memory on a stream of their own.)
  virtual std::unique_ptr<FrameRead> read_frame(size_t slots, bool changes);
  // Brings `bonds`, what the previous call gave, up to date (bond_changes applied).
  void update_bonds(BondLists& bonds) {
    BondChanges changes;
    bond_changes(bonds.neighbor.size(), changes);
    changes.apply_to(bonds);
  }
  virtual int64_t broken_bonds() = 0;
  // Energy terms at the current state, and the work and released energy since the start.
  virtual Energy energy() = 0;
  // Index of the first particle whose displacement, velocity or force is not finite; -1 if none.
  virtual int64_t first_non_finite() = 0;
  virtual KernelStats& stats() = 0;
  virtual void save(EngineSnapshot& out) = 0;
  // Throws std::invalid_argument, changing nothing, when the snapshot's sizes are not this
  // engine's (another scene or scale).
  virtual void restore(const EngineSnapshot& in) = 0;
  // Puts back the per-particle fields of `in` (displacements, velocities, forces, ...) and its
  // step and time, the bonds left as they are: for a caller that knows no bond changed since `in`
  // was saved (the stable step's probes, cuda/engine/stable_step.h), where a whole restore would
  // move and check every bond slot. A partitioned run restores everything.
  virtual void restore_particles(const EngineSnapshot& in) = 0;
  // Changes the fixed dt of the steps to come (the stable step measured on the engine itself,
  // cuda/engine/stable_step.h, chooses it after the set-up): recorded step graphs are dropped.
  virtual void set_time_step(double dt) = 0;
  // Stable time step from the families as built (Silling & Askari 2005, eq. 29):
  // min_i sqrt(2 rho_i / sum_j beta V_j c / |xi_j|); infinite for particles without bonds.
  virtual double critical_time_step() const = 0;
  // Bytes of backend memory held by the engine.
  virtual size_t memory_bytes() const = 0;
  // The ghost surface correction's set-up (cuda/engine/surface_ghosts.h): particles with ghosts
  // (and of them those on the linear fit), and those that miss bonds but have none (thin
  // families, pre-cracks).
  virtual SurfaceGhostCounts surface_ghosts() const { return {}; }
  // Force passes run (one per step, and one at set-up) and those `springforces` ran screened
  // (cuda/kernels/bond_screen.h).
  virtual int64_t force_passes() const = 0;
  virtual int64_t screened_passes() const = 0;
  // Steps run as CUDA graphs (cuda/engine/step_graphs.h); 0 on the CPU and on ranks.
  virtual int64_t graphed_steps() const { return 0; }
  // Per rank of a partitioned run, in rank order; empty for a run on one rank.
  virtual std::vector<RankStats> rank_stats() { return {}; }
  // Where the set-up's time went, stage by stage (a partitioned run: rank 0's engine).
  virtual std::vector<SetupStage> setup_stages() const { return {}; }
  // The colliders' poses and velocities now (free ones as the particles moved them).
  virtual std::vector<Collider> colliders() = 0;
};

std::unique_ptr<Engine> make_cpu_engine(const SimulationInput& in);
// A CPU engine of the whole input in this process alone, also under mpirun (where
// make_cpu_engine would be a partitioned run's): each rank may build one for itself, e.g. to read
// an earlier run's checkpoint (host/app/shards_pattern.h).
std::unique_ptr<Engine> make_local_cpu_engine(const SimulationInput& in);
// Throws std::runtime_error when CUDA is not compiled in or no device is usable.
std::unique_ptr<Engine> make_cuda_engine(const SimulationInput& in);
std::unique_ptr<Engine> make_engine(Backend b, const SimulationInput& in);

// True when the build has CUDA and a device answers; otherwise `why` says what is missing.
bool cuda_device_available(std::string* why = nullptr);
// Free memory of the CUDA device; 0 when there is none.
size_t cuda_free_bytes();

// Named ranges for GPU profilers (NVTX push/pop); no-ops in a build without CUDA.
void profiler_range_push(const char* name);
void profiler_range_pop();

}  // namespace pd
