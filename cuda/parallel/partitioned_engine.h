// A run over several ranks (MPI; one GPU or one CPU socket each) that answers as one engine of
// the whole run. Every rank builds the same input, partitions it the same way
// (cuda/parallel/partition.h) and runs an EngineImpl over its own particles and their ghosts,
// whose halo is refreshed inside the step. Rank 0 drives: the program runs there as it does
// with one rank, and each Engine call is broadcast as a command that every rank carries out
// together (gathers, reductions). The other ranks only serve those commands.
//
// The same bits as one rank: families and contact lists keep partners in global index order
// (order_of), so every per-particle sum runs in the order of the one-rank run; the energy is
// summed on rank 0 over the gathered per-particle terms by the same reduction; frames, bonds and
// snapshots are gathered into the one-rank layout (a checkpoint resumes on any number of ranks).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cuda/engine/engine_impl.h"
#include "cuda/parallel/comm.h"
#include "cuda/parallel/partition.h"

namespace pd {

template <class Exec>
class PartitionedEngine final : public Engine {
 public:
  PartitionedEngine(const SimulationInput& in, std::shared_ptr<Comm> comm, const std::string& device)
      : comm_(std::move(comm)), n_(int64_t(in.particles.size())) {
    auto t0 = std::chrono::steady_clock::now();
    build(in, device, partition_particles(in.particles, in.materials, comm_->size()), t0);
    // The split weighs each particle by the bonds it is expected to have, exact on a lattice; where
    // the families built are off by more than kResplitAbove (a mesh's elements of uneven size), the
    // whole run is split again on their sizes, which every rank now knows, and set up anew.
    first_imbalance_ = bond_imbalance();
    if (first_imbalance_ > kResplitAbove) {
      t0 = std::chrono::steady_clock::now();
      const std::vector<int32_t> sizes = global_count_;
      local_.reset();  // (its memory back before the next one's)
      build(in, device, partition_particles(in.particles, in.materials, comm_->size(), sizes), t0);
    }
    global_families();
    device_ = local_->device_name() + " x " + std::to_string(comm_->size()) + " ranks";
    critical_dt_ = comm_->min(local_->critical_time_step());
    memory_ = size_t(comm_->sum(int64_t(local_->memory_bytes())));
    const RankStats mine = local_->local_rank_stats();
    if (comm_->rank() == 0) report_balance(in, mine);
  }

  ~PartitionedEngine() override {
    if (comm_->rank() == 0) command(Op::kFinish);
  }

  // A rank other than 0: carries out rank 0's commands until it finishes.
  void serve() {
    for (;;) {
      int64_t message[2] = {0, 0};
      comm_->broadcast(message, sizeof(message), 0);
      const Op op = Op(message[0]);
      if (op == Op::kFinish) return;
      perform(op, message[1]);
    }
  }

  Backend backend() const override { return local_->backend(); }
  std::string device_name() const override { return device_; }
  const FamilyStats& family_stats() const override { return family_; }
  void advance(int64_t steps) override { command(Op::kAdvance, steps); }
  int64_t step() const override { return local_->step(); }
  double time() const override { return local_->time(); }
  void read_state(ParticleState& out) override {
    command(Op::kReadState);
    out = std::move(state_out_);
  }
  void read_bonds(BondLists& out) override {
    command(Op::kReadBonds);
    out = std::move(bonds_out_);
  }
  int64_t broken_bonds() override {
    command(Op::kBroken);
    return count_out_;
  }
  Energy energy() override {
    command(Op::kEnergy);
    return energy_out_;
  }
  int64_t first_non_finite() override {
    command(Op::kNonFinite);
    return count_out_;
  }
  KernelStats& stats() override { return local_->stats(); }
  void save(EngineSnapshot& out) override {
    command(Op::kSave);
    out = std::move(snapshot_);
  }
  void restore(const EngineSnapshot& in) override {
    check_global_sizes(in);
    snapshot_ = in;
    command(Op::kRestore);
    snapshot_ = {};
  }
  double critical_time_step() const override { return critical_dt_; }
  void restore_particles(const EngineSnapshot& in) override { restore(in); }
  void set_time_step(double dt) override {
    int64_t bits = 0;
    std::memcpy(&bits, &dt, sizeof bits);
    command(Op::kSetTimeStep, bits);
  }
  size_t memory_bytes() const override { return memory_; }
  int64_t force_passes() const override { return local_->force_passes(); }
  int64_t screened_passes() const override { return local_->screened_passes(); }
  std::vector<Collider> colliders() override { return local_->colliders(); }
  // Rank 0's: the partition, then its engine's stages.
  std::vector<SetupStage> setup_stages() const override {
    std::vector<SetupStage> stages = {{"partition", setup_seconds_[0]}};
    for (const SetupStage& s : local_->setup_stages()) stages.push_back(s);
    return stages;
  }
  std::vector<RankStats> rank_stats() override {
    command(Op::kRankStats);
    return std::move(ranks_out_);
  }

 private:
  // The largest rank's bonds over the mean at which the run is split again.
  static constexpr double kResplitAbove = 1.01;

  // This rank's engine on `partition` (set-up times added to the stages' sums).
  void build(const SimulationInput& in, const std::string& device, Partition partition,
             std::chrono::steady_clock::time_point t0) {
    partition_ = std::move(partition);
    layout_ = rank_layout(partition_, comm_->rank());
    own_by_global_.resize(size_t(layout_.owned));
    for (int32_t i = 0; i < layout_.owned; ++i) own_by_global_[size_t(i)] = {layout_.global[size_t(i)], i};
    std::sort(own_by_global_.begin(), own_by_global_.end());
    SimulationInput local_input;
    local_input.particles = local_particles(in.particles, layout_);
    local_input.materials = in.materials;
    local_input.step = in.step;
    local_input.motion = in.motion;
    local_input.colliders = in.colliders;
    local_input.collider_grids = in.collider_grids;
    local_input.collider_probes = in.collider_probes;
    local_input.cuts = in.cuts;
    local_input.face_bonds = local_face_bonds(in.face_bonds, layout_, in.particles.size());
    local_input.contact = in.contact;
    local_input.lattice_families = false;
    local_input.screen = in.screen;
    // Chosen from the whole run's particles, so each rank sums a particle's bonds as one rank does.
    local_input.bond_threads = bond_threads_of(in);
    if (local_input.particles.size() == 0)
      throw std::runtime_error("it holds no particle: run on fewer ranks");  // (named "rank R of N: ")
    const auto t1 = std::chrono::steady_clock::now();
    local_ =
        std::make_unique<EngineImpl<Exec>>(local_input, device, &layout_, comm_.get(),
                                           [&](const BondLists& local) { return rank_lattice(in, local); });
    setup_seconds_[0] += std::chrono::duration<double>(t1 - t0).count();
    setup_seconds_[1] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }

  // The families' bonds on each rank (every rank knows every particle's family size).
  std::vector<int64_t> rank_bonds() const {
    std::vector<int64_t> bonds(size_t(comm_->size()), 0);
    for (int r = 0; r < comm_->size(); ++r)
      for (int32_t g : partition_.owned[size_t(r)]) bonds[size_t(r)] += global_count_[size_t(g)];
    return bonds;
  }

  // The largest rank's bonds over the mean.
  double bond_imbalance() const {
    const std::vector<int64_t> bonds = rank_bonds();
    const double mean =
        double(std::accumulate(bonds.begin(), bonds.end(), int64_t(0))) / double(bonds.size());
    return mean > 0 ? double(*std::max_element(bonds.begin(), bonds.end())) / mean : 1.0;
  }

  enum class Op : int64_t {
    kFinish,
    kAdvance,
    kReadState,
    kReadBonds,
    kBroken,
    kEnergy,
    kNonFinite,
    kSave,
    kRestore,
    kRankStats,
    kSetTimeStep
  };

  // Rank 0: every rank carries out `op` together.
  void command(Op op, int64_t arg = 0) {
    int64_t message[2] = {int64_t(op), arg};
    comm_->broadcast(message, sizeof(message), 0);
    if (op != Op::kFinish) perform(op, arg);
  }

  void perform(Op op, int64_t arg) {
    switch (op) {
      case Op::kAdvance:
        local_->advance(arg);
        break;
      case Op::kReadState:
        gather_state();
        break;
      case Op::kReadBonds:
        gather_bonds();
        break;
      case Op::kBroken:
        count_out_ = comm_->sum(local_->broken_bonds());
        break;
      case Op::kEnergy:
        gather_energy();
        break;
      case Op::kNonFinite: {
        const int64_t bad = local_->first_non_finite();
        const double first = comm_->min(bad < 0 ? 1e300 : double(layout_.global[size_t(bad)]));
        count_out_ = first < 1e300 ? int64_t(first) : -1;
        break;
      }
      case Op::kSave:
        gather_snapshot();
        break;
      case Op::kRestore:
        scatter_snapshot();
        break;
      case Op::kRankStats:
        gather_rank_stats();
        break;
      case Op::kSetTimeStep: {
        double dt = 0;
        std::memcpy(&dt, &arg, sizeof dt);
        local_->set_time_step(dt);
        break;
      }
      case Op::kFinish:
        break;
    }
  }

  // ---- The one-rank layout of the families ----------------------------------------------------
  int64_t global_slot(int32_t g, int32_t k) const {
    return global_offset_[size_t(g) / kSliceWidth] + int64_t(k) * kSliceWidth + g % kSliceWidth;
  }

  // During the rank engine's set-up, with its families as built (cuts applied): every rank
  // learns the one-rank layout (global_layout), and box-grid bodies get their lattice tables as
  // one rank makes them, each rank building its own particles' part from its own families (the
  // fit and the stencils' offsets combined over the ranks). Empty when the run has none.
  LatticeFamilies rank_lattice(const SimulationInput& in, const BondLists& local) {
    global_layout(local);
    if (!in.lattice_families) return {};
    const auto t0 = std::chrono::steady_clock::now();
    struct OverRanks final : StencilReduce {
      PartitionedEngine* engine;
      explicit OverRanks(PartitionedEngine* e) : engine(e) {}
      bool all(bool mine) override { return engine->comm_->min(mine ? 1.0 : 0.0) > 0; }
      std::vector<int32_t> union_of(const std::vector<int32_t>& mine) override {
        std::vector<std::vector<char>> parts;
        engine->comm_->gather(to_bytes(mine), parts, 0);
        std::vector<int32_t> all;
        for (const auto& part : parts) {
          const std::vector<int32_t> v = from_bytes<int32_t>(part);
          all.insert(all.end(), v.begin(), v.end());
        }
        std::sort(all.begin(), all.end());
        all.erase(std::unique(all.begin(), all.end()), all.end());
        engine->broadcast_vector(all);
        return all;
      }
    } reduce(this);
    LatticeFamilies part =
        rank_lattice_families(in.particles, in.materials, local, layout_.global, layout_.owned, reduce);
    setup_seconds_[2] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return part;
  }

  // Every rank learns every particle's family size: the one-rank sliced-ELL layout follows.
  void global_layout(const BondLists& local) {
    local_bonds_ = local;
    std::vector<int32_t> own(local_bonds_.count.begin(), local_bonds_.count.begin() + layout_.owned);
    global_count_ = gather_particles(own);
    global_count_.resize(size_t(n_));
    comm_->broadcast(global_count_.data(), global_count_.size() * sizeof(int32_t), 0);
    const int64_t slices = (n_ + kSliceWidth - 1) / kSliceWidth;
    global_offset_.assign(size_t(slices + 1), 0);
    for (int64_t s = 0; s < slices; ++s) {
      int32_t longest = 0;
      for (int64_t i = s * kSliceWidth; i < n_ && i < (s + 1) * kSliceWidth; ++i)
        longest = std::max(longest, global_count_[size_t(i)]);
      global_offset_[size_t(s + 1)] = global_offset_[size_t(s)] + int64_t(longest) * kSliceWidth;
    }
  }

  // The family statistics of the whole run.
  void global_families() {
    const FamilyStats& mine = local_->family_stats();
    family_.bonds = comm_->sum(mine.bonds);
    family_.min = *std::min_element(global_count_.begin(), global_count_.end());
    family_.max = *std::max_element(global_count_.begin(), global_count_.end());
    family_.mean = double(family_.bonds) / double(n_);
    family_.slots = global_offset_.back();
    family_.lattice_particles = comm_->sum(mine.lattice_particles);
    family_.lattice_listed = comm_->sum(mine.lattice_listed);
    family_.surface_rows = comm_->sum(mine.surface_rows);  // (each rank's table its own)
    family_.cuts.removed = comm_->sum(mine.cuts.removed);
    family_.cuts.weakened = comm_->sum(mine.cuts.weakened);
  }

  // ---- Gathers to rank 0, in global order ----------------------------------------------------
  // The own entries of a per-particle array (local order), as the whole run's array on rank 0.
  template <class T>
  std::vector<T> gather_particles(const std::vector<T>& local) {
    std::vector<T> own(local.begin(), local.begin() + std::min<size_t>(local.size(), size_t(layout_.owned)));
    std::vector<std::vector<char>> parts;
    comm_->gather(to_bytes(own), parts, 0);
    std::vector<T> all;
    if (comm_->rank() != 0) return all;
    all.resize(size_t(n_));
    for (int r = 0; r < comm_->size(); ++r) {
      const std::vector<T> values = from_bytes<T>(parts[size_t(r)]);
      const auto& ids = partition_.owned[size_t(r)];
      for (size_t k = 0; k < values.size() && k < ids.size(); ++k) all[size_t(ids[k])] = values[k];
    }
    return all;
  }

  // The own families' entries of a per-slot array (local layout), in the one-rank layout on rank 0.
  template <class T>
  std::vector<T> gather_slots(const std::vector<T>& local) {
    std::vector<T> own;
    for (int32_t i = 0; i < layout_.owned; ++i)
      for (int32_t k = 0; k < local_bonds_.count[size_t(i)]; ++k)
        own.push_back(local[size_t(local_slot(i, k))]);
    std::vector<std::vector<char>> parts;
    comm_->gather(to_bytes(own), parts, 0);
    std::vector<T> all;
    if (comm_->rank() != 0) return all;
    all.assign(size_t(std::max<int64_t>(global_offset_.back(), 1)), T{});
    for (int r = 0; r < comm_->size(); ++r) {
      const std::vector<T> values = from_bytes<T>(parts[size_t(r)]);
      size_t at = 0;
      for (int32_t g : partition_.owned[size_t(r)])
        for (int32_t k = 0; k < global_count_[size_t(g)]; ++k) all[size_t(global_slot(g, k))] = values[at++];
    }
    return all;
  }

  int64_t local_slot(int32_t i, int32_t k) const {
    return local_bonds_.slice_offset[size_t(i) / kSliceWidth] + int64_t(k) * kSliceWidth + i % kSliceWidth;
  }

  // Partner entries (index, or ~index once broken) from local to global indices and back.
  std::vector<int32_t> partners_to_global(std::vector<int32_t> nb) const {
    for (int32_t i = 0; i < layout_.owned; ++i)
      for (int32_t k = 0; k < local_bonds_.count[size_t(i)]; ++k) {
        int32_t& e = nb[size_t(local_slot(i, k))];
        const int32_t g = layout_.global[size_t(bond_partner(e))];
        e = bond_intact(e) ? g : ~g;
      }
    return nb;
  }
  int32_t local_index(int32_t g) const {
    const auto own =
        std::lower_bound(own_by_global_.begin(), own_by_global_.end(), std::make_pair(g, int32_t(0)));
    if (own != own_by_global_.end() && own->first == g) return own->second;
    const auto own_end = layout_.global.begin() + layout_.owned;
    const auto it = std::lower_bound(own_end, layout_.global.end(), g);
    if (it == layout_.global.end() || *it != g) throw std::logic_error("partner outside the rank's ghosts");
    return int32_t(it - layout_.global.begin());
  }

  void gather_state() {
    ParticleState local;
    local_->read_state(local);
    state_out_ = {};
#define PD_GATHER_FRAME(name, Type, length, when, saved, halo, frame) \
  PD_IF_FRAME(frame, state_out_.name = gather_particles(local.name);)
    PD_PARTICLE_FIELDS(PD_GATHER_FRAME)
#undef PD_GATHER_FRAME
  }

  void gather_bonds() {
    BondLists local;
    local_->read_bonds(local);
    bonds_out_ = {};
    bonds_out_.neighbor = gather_slots(partners_to_global(local.neighbor));
    if (comm_->rank() != 0) return;
    bonds_out_.slice_offset = global_offset_;
    bonds_out_.count = global_count_;
  }

  void gather_rank_stats() {
    std::vector<std::vector<char>> parts;
    comm_->gather(to_bytes(std::vector<RankStats>{local_->local_rank_stats()}), parts, 0);
    ranks_out_.clear();
    for (const auto& part : parts) ranks_out_.push_back(from_bytes<RankStats>(part).at(0));
  }

  void gather_energy() {
    const std::vector<Energy> terms = gather_particles(local_->owned_energies());
    energy_out_ = comm_->rank() == 0 ? local_->sum_energies(terms) : Energy{};
  }

  // Each saved field in the one-rank layout (per particle or per slot, by the table's length).
  template <FieldLength kLength, class T>
  std::vector<T> gather_field(const std::vector<T>& local) {
    if (local.empty()) return {};
    if constexpr (kLength == kSlots) return gather_slots(local);
    return gather_particles(local);
  }

  void gather_snapshot() {
    EngineSnapshot local;
    local_->save(local);
    local.neighbor = partners_to_global(local.neighbor);
    snapshot_ = {};
    snapshot_.step = local.step;
    snapshot_.time = local.time;
    snapshot_.free_bodies = local.free_bodies;  // (alike on every rank)
#define PD_GATHER_SAVED(name, Type, length, when, saved, ...) \
  PD_IF_SAVED(saved, snapshot_.name = gather_field<length>(local.name);)
    PD_STATE_FIELDS(PD_GATHER_SAVED)
#undef PD_GATHER_SAVED
  }

  // ---- Restore: rank 0's snapshot, each rank's part ------------------------------------------
  // Rank 0, before any rank is told: a snapshot of another run is refused, changing nothing.
  void check_global_sizes(const EngineSnapshot& in) const {
    for_each_snapshot_field(in, [&](const char* what, const auto& v) {
      const size_t want = expected_size(what);
      if (!v.empty() && v.size() != want)
        throw std::invalid_argument(std::string("snapshot ") + what + " has " + std::to_string(v.size()) +
                                    " entries, the engine " + std::to_string(want));
    });
  }
  size_t expected_size(const char* what) const {
#define PD_SIZE_OF(name, Type, length, when, saved, ...) \
  if (std::string(#name) == what)                        \
    return length == kSlots ? size_t(std::max<int64_t>(global_offset_.back(), 1)) : size_t(n_);
    PD_STATE_FIELDS(PD_SIZE_OF)
#undef PD_SIZE_OF
    return 0;
  }

  template <class T>
  void broadcast_vector(std::vector<T>& v) {
    uint64_t size = v.size();
    comm_->broadcast(&size, sizeof(size), 0);
    v.resize(size_t(size));
    comm_->broadcast(v.data(), v.size() * sizeof(T), 0);
  }

  void scatter_snapshot() {
    EngineSnapshot& all = snapshot_;
    comm_->broadcast(&all.step, sizeof(all.step), 0);
    comm_->broadcast(&all.time, sizeof(all.time), 0);
    for_each_snapshot_field(all, [&](const char*, auto& v) { broadcast_vector(v); });
    broadcast_vector(all.free_bodies);
    EngineSnapshot local;
    local_->save(local);  // the local sizes
    local.step = all.step;
    local.time = all.time;
    local.free_bodies = all.free_bodies;
#define PD_SCATTER_SAVED(name, Type, length, when, saved, ...) \
  PD_IF_SAVED(saved, scatter_field<length>(all.name, local.name);)
    PD_STATE_FIELDS(PD_SCATTER_SAVED)
#undef PD_SCATTER_SAVED
    // Partners back to local indices.
    for (int32_t i = 0; i < layout_.owned; ++i)
      for (int32_t k = 0; k < local_bonds_.count[size_t(i)]; ++k) {
        int32_t& e = local.neighbor[size_t(local_slot(i, k))];
        const int32_t l = local_index(bond_partner(e));
        e = bond_intact(e) ? l : ~l;
      }
    local_->restore_with_mirror(local, plastic_mirror(all));
    if (comm_->rank() != 0) snapshot_ = {};
  }

  template <FieldLength kLength, class T>
  void scatter_field(const std::vector<T>& all, std::vector<T>& local) {
    if (all.empty() || local.empty()) return;
    if constexpr (kLength == kSlots) {
      for (int32_t i = 0; i < layout_.owned; ++i)
        for (int32_t k = 0; k < local_bonds_.count[size_t(i)]; ++k)
          local[size_t(local_slot(i, k))] = all[size_t(global_slot(layout_.global[size_t(i)], k))];
    } else {
      // (own and bond ghosts; contact ghosts are gathered again at the next contact build)
      for (size_t i = 0; i < local.size() && i < layout_.global.size(); ++i)
        local[i] = all[size_t(layout_.global[i])];
    }
  }

  // Each own bond end's mirror: the partner's e^p on the same bond (plasticity.h), from the whole
  // run's history.
  std::vector<real> plastic_mirror(const EngineSnapshot& all) const {
    if (all.plastic.empty()) return {};
    BondLists global;
    global.slice_offset = global_offset_;
    global.count = global_count_;
    global.neighbor = all.neighbor;
    const BondsView b = global.view();
    std::vector<real> mirror(local_bonds_.neighbor.size(), real(0));
    for (int32_t i = 0; i < layout_.owned; ++i) {
      const int32_t g = layout_.global[size_t(i)];
      for (int32_t k = 0; k < global_count_[size_t(g)]; ++k) {
        const int32_t j = bond_partner(all.neighbor[size_t(global_slot(g, k))]);
        const int32_t q = position_in_family(b, j, g);
        if (q >= 0) mirror[size_t(local_slot(i, k))] = all.plastic[size_t(global_slot(j, q))];
      }
    }
    return mirror;
  }

  // Rank 0: particles, ghosts and bonds per rank, and the imbalance of the bonds built (largest
  // over mean), with the one the estimate gave where the run was split again on the families.
  void report_balance(const SimulationInput& in, const RankStats& rank0) const {
    const PartitionBalance b = partition_balance(partition_, in.particles, in.materials);
    const auto [lo, hi] = std::minmax_element(b.particles.begin(), b.particles.end());
    const auto [glo, ghi] = std::minmax_element(b.ghosts.begin(), b.ghosts.end());
    const std::vector<int64_t> bonds = rank_bonds();
    const auto [blo, bhi] = std::minmax_element(bonds.begin(), bonds.end());
    char again[96] = "";
    if (first_imbalance_ > kResplitAbove)
      std::snprintf(again, sizeof(again), " (split again on the families: %.3f on the estimate)",
                    first_imbalance_);
    std::printf(
        "ranks      %d: particles per rank %lld to %lld, ghosts %lld to %lld, bonds %lld to %lld, "
        "imbalance %.3f%s\n",
        comm_->size(), (long long)*lo, (long long)*hi, (long long)*glo, (long long)*ghi, (long long)*blo,
        (long long)*bhi, bond_imbalance(), again);
    std::printf("halo       %s, %s\n", rank0.halo_transport,
                rank0.overlapped ? "interior forces computed while it travels" : "not overlapped");
    std::printf("set-up     rank 0: partition %.2f s, its engine %.2f s (of which lattice tables %.2f s)\n",
                setup_seconds_[0], setup_seconds_[1], setup_seconds_[2]);
  }

  std::shared_ptr<Comm> comm_;
  int64_t n_ = 0;  // particles of the whole run
  Partition partition_;
  RankLayout layout_;
  std::vector<std::pair<int32_t, int32_t>> own_by_global_;  // (global, local) of the own particles
  double setup_seconds_[3] = {0, 0, 0};  // partition, rank engine, lattice tables (within it)
  double first_imbalance_ = 1;           // of the bonds on the estimate's split
  std::unique_ptr<EngineImpl<Exec>> local_;
  std::string device_;
  FamilyStats family_;
  double critical_dt_ = 0;
  size_t memory_ = 0;
  BondLists local_bonds_;               // the rank's families as built (layout, sizes)
  std::vector<int32_t> global_count_;   // every particle's family size
  std::vector<int64_t> global_offset_;  // the one-rank slice offsets
  // Rank 0's results of the last command.
  ParticleState state_out_;
  BondLists bonds_out_;
  EngineSnapshot snapshot_;
  Energy energy_out_;
  int64_t count_out_ = 0;
  std::vector<RankStats> ranks_out_;
};

// The engine of this rank of a partitioned run. Rank 0 gets it; any other rank serves rank 0's
// commands and then ends its process here. An error on one rank ends every rank (the others
// may be waiting for it), with its message.
template <class Exec>
std::unique_ptr<Engine> make_partitioned_engine(const SimulationInput& in, std::shared_ptr<Comm> comm,
                                                const std::string& device) {
  const int rank = comm->rank();
  std::unique_ptr<PartitionedEngine<Exec>> engine;
  try {
    engine = std::make_unique<PartitionedEngine<Exec>>(in, comm, device);
    if (rank == 0) return engine;
    engine->serve();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: rank %d of %d: %s\n", rank, comm->size(), e.what());
    comm->abort(2);
  }
  engine.reset();
  std::fflush(stdout);
  leave_world();
  std::exit(0);
}

}  // namespace pd
