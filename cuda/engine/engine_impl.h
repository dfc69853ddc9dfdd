// The engine for one backend: sets up the state (engine_state.h), the families
// (family_builder.h) and the contact lists (contact_lists.h), and runs the step as the sequence
// of the seven kernels. Included by cuda/engine/engine_cpu.cpp (CpuExec) and
// cuda/engine/engine_cuda.cu (CudaExec).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>

#include "cuda/engine/bond_threads.h"
#include "cuda/engine/collider_grid.h"
#include "cuda/engine/collider_reactions.h"
#include "cuda/engine/contact_lists.h"
#include "cuda/engine/contact_rebuild.h"
#include "cuda/engine/engine.h"
#include "cuda/engine/engine_state.h"
#include "cuda/engine/family_builder.h"
#include "cuda/engine/frame_reads.h"
#include "cuda/engine/free_bodies.h"
#include "cuda/engine/step_graphs.h"
#include "cuda/engine/surface_ghosts.h"
#include "cuda/launch.h"
#include "cuda/parallel/contact_ghosts.h"
#include "cuda/parallel/halo.h"

namespace pd {

template <class Exec>
class EngineImpl final : public Engine {
 public:
  // One rank of a partitioned run when `rank` is given (cuda/parallel/partitioned_engine.h): `in`
  // holds the rank's particles in its layout's order, its own first; the kernels of a step run
  // over those, and the ghosts after them are refreshed from their owners through `comm`.
  // `rank_lattice` gives the rank its part of the whole run's lattice tables from its families
  // as built (empty tables: none).
  EngineImpl(const SimulationInput& in, std::string device, const RankLayout* rank = nullptr,
             Comm* comm = nullptr, const std::function<LatticeFamilies(const BondLists&)>& rank_lattice = {})
      : exec_(&stats_),
        mem_(&exec_),
        device_(std::move(device)),
        materials_(in.materials),
        step_params_(in.step),
        motion_(in.motion),
        contact_(in.contact),
        screen_(in.screen),
        bond_threads_(bond_threads_of(in)) {
    features_ = features_of(materials_, contact_);
    // Graphs where no host work falls between the step's launches (step_graphs.h).
    const bool graphs_wanted = step_graphs_wanted(in);  // (a bad PERIFRAC_STEP_GRAPHS fails on the CPU too)
    const ContactRebuild contact_rebuild = requested_contact_rebuild(in);  // (and a bad ..._CONTACT_REBUILD)
    exec_.set_overlap_launches(overlapped_launches_wanted());              // (and ..._OVERLAP_LAUNCHES)
    graphs_ = Exec::kGraphs && graphs_wanted && !rank && !scripted_motion_ && free_.empty() &&
              !moving_colliders_ && !contact_ && step_params_.n_projectiles == 0;
    colliders_host_ = in.colliders;
    if (in.particles.size() == 0) throw std::runtime_error("the scene has no particles");
    stage_start_ = std::chrono::steady_clock::now();
    state_.upload(mem_, in.particles,
                  FieldNeeds{features_.state_based, features_.plastic, false, rank != nullptr,
                             features_.surface_factors});
    owned_ = state_.n;
    held_ = state_.n;
    if (rank) {
      owned_ = rank->owned;
      interior_ = rank->interior;
      state_.global_id.upload(rank->global);
      const HaloOptions halo = halo_options_from_env();
      halo_ = Halo<Exec>(mem_, *rank, *comm, halo);
      overlap_ = halo.overlap < 0 ? !halo_.device_link() : halo.overlap == 1;
      ghosts_ = ContactGhosts<Exec>(*rank, *comm);
      world_ = comm;
    }
    end_stage("upload");
    build_families(mem_, state_, owned_, materials_, features_, backend(), family_);
    exec_.set_team_block(team_block_of(in, features_.state_based, family_.mean, bond_threads_));
    end_stage("families");
    // The surface correction's factors come from the families before the pre-cracks: a crack is
    // not a surface of the body (none formed in the run is either; docs/validation.md,
    // notched_bar_pmb).
    if (features_.surface_factors) set_up_surface_correction();
    end_stage("surface correction");
    // The families on the host, downloaded once for the stages below that read them.
    BondLists host_bonds;
    bool have_host_bonds = false;
    auto bonds_on_host = [&]() -> const BondLists& {
      if (!have_host_bonds) download_bonds(state_, host_bonds);
      have_host_bonds = true;
      return host_bonds;
    };
    // The ghost correction's families before the pre-cracks, for the same reason.
    BondLists uncut;
    if (features_.ghosts) download_bonds(state_, uncut);
    if (!in.cuts.empty() || !in.particles.shard.empty()) {
      features_.weak_bonds = apply_cuts(mem_, state_, owned_, in, family_, host_bonds);
      have_host_bonds = true;
      if (features_.surface_factors) launch_surface_bond_factors(exec_, particles(), bonds(), materials_);
      end_stage("pre-cracks");
    }
    // (Lattice offsets are indices of the whole run. Without a box-grid body, as in scenes of
    // meshes, tets and Voronoi cells, the families are not downloaded for the tables: the vase at
    // Levine's size, 0.12 s of its set-up.)
    if (in.lattice_families && !rank && box_grid_particles(in.particles) > 0)
      features_.lattice = build_lattice_families(mem_, state_, in.particles, materials_, features_.weak_bonds,
                                                 lattice_, family_, bonds_on_host());
    if (rank_lattice) {
      features_.lattice = upload_lattice_families(mem_, state_, rank_lattice(bonds_on_host()),
                                                  features_.weak_bonds, lattice_, family_, bonds_on_host());
      features_.lattice_listed = features_.lattice;
    }
    if (features_.surface_factors && !lattice_.empty())
      upload_surface_rows(mem_, state_, lattice_, family_, bonds_on_host());
    end_stage("lattice tables");
    // Bond-based only: the state-based passes' dilatation loop lost 4-10% so ordered (bench/NOTES.md).
    // (A partitioned rank launches ranges of its own.)
    const int balance = balance_window();  // (a bad PERIFRAC_BALANCE_WINDOW fails on the CPU too)
    if (Exec::kDevice && !rank && !features_.lattice && !features_.state_based && bond_threads_ > 1) {
      std::vector<int32_t> counts;
      state_.count.download(counts);  // (the counts alone: the whole families are not needed)
      const std::vector<int32_t> order = balanced_particle_order(counts, balance);
      if (!order.empty()) balanced_ids_ = mem_.make_from(order);
    }
    std::vector<double> ghost_rate;
    if (features_.ghosts) {
      if (rank)
        throw std::invalid_argument(
            "the ghost surface correction (surface_correction = \"ghosts\") runs on one rank "
            "(allowed: the run without mpirun -np N, or surface_correction = true)");
      set_up_ghosts(in.particles, in.body_solids.get(), uncut, bonds_on_host().count, ghost_rate);
      ghost_threads_ = ghost_threads_for(ghost_counts_.ghosted, requested_bond_threads(in));
      uncut = BondLists();
      end_stage("surface ghosts");
    }
    host_bonds = BondLists();
    double collider_stiffness = 0;
    for (const Collider& c : colliders_host_)  // (the indent law's stiffness grows with the depth: not here)
      if (c.law == kLawPenalty) collider_stiffness = std::max(collider_stiffness, double(c.stiffness));
    critical_dt_ = stable_time_step(mem_, particles(), bonds(), materials_, collider_stiffness, ghost_rate);
    // The listed bond-based particles' factors with their partial volumes folded in, now that
    // nothing reads the plain ones (surface_correction.h folds_partial_volume).
    if (features_.surface_factors) launch_surface_bond_factors(exec_, particles(), bonds(), materials_, true);
    end_stage("stable step");
    if (features_.state_based) {
      set_up_state_based();
      if (features_.ghosts) launch_ghost_weighted_volume(exec_, particles(), ghost_view());
      end_stage("state-based");
    }
    if (contact_)
      contacts_.allocate(mem_, state_.n, materials_, contact_rebuild == ContactRebuild::kIncremental,
                         step_params_.gravity);
    // The velocity update's floor test reads a particle's reference position only below this
    // (below_floor). A partitioned rank's contact ghosts arrive later with positions of their
    // own: it keeps -infinity, reading every one as before.
    if (!rank) {
      real lowest = real(INFINITY);
      for (const Vec3& x : in.particles.rest) lowest = std::min(lowest, x.y);
      step_params_.lowest_rest_y = lowest;
    }
    body_forces_ = step_params_.n_projectiles > 0 || step_params_.gravity.x != 0 ||
                   step_params_.gravity.y != 0 || step_params_.gravity.z != 0 || !colliders_host_.empty();
    fusion_.init = !features_.state_based;
    fusion_.gravity = body_forces_ && step_params_.n_projectiles == 0 && colliders_host_.empty();
    fusion_.steps_meet = !scripted_motion_ && free_.empty() && !moving_colliders_;
    colliders_ = mem_.make_from(colliders_host_);
    step_params_.colliders = view_of(colliders_);
    collider_spheres_ = mem_.template make<Vec4>(colliders_host_.size());
    step_params_.collider_spheres = view_of(collider_spheres_);
    for (real v : in.particles.volume)
      largest_particle_ = std::max(largest_particle_, real(std::cbrt(double(v))));
    grids_host_ = in.collider_grids;
    probes_ = in.collider_probes;
    collider_grids_ = mem_.make_from(grids_host_);
    step_params_.collider_grids = view_of(collider_grids_);
    motion_.apply(time_, step_params_);
    pose_colliders(time_);
    compute_forces();
    if (!free_.empty()) {
      reactions_ = ColliderReactions<Exec>(mem_, owned_, free_.colliders(), colliders_host_.size());
      react_and_touch();
    }
    end_stage("first forces");
    exec_.flush_stats();
  }

  Backend backend() const override { return Exec::kDevice ? Backend::kCuda : Backend::kCpu; }
  std::string device_name() const override { return device_; }
  const FamilyStats& family_stats() const override { return family_; }
  int64_t step() const override { return step_; }
  double time() const override { return time_; }
  KernelStats& stats() override { return stats_; }

  void advance(int64_t steps) override {
    const auto t0 = std::chrono::steady_clock::now();
    const real dt = step_params_.dt;
    bool end_pending = false;  // the last step's velocity update waits to run with this one's position update
    for (int64_t s = 0; s < steps; ++s) {
      if (graphs_ && steps - s >= kGraphSteps) {
        if (end_pending) end_step();
        end_pending = false;
        run_step_graph();
        s += kGraphSteps - 1;
        continue;
      }
      step_params_.time = real(time_ + dt);
      if (scripted_motion_) motion_.apply(time_ + dt, step_params_);
      if (!free_.empty()) {  // velocity Verlet, as the particles: half kick, drift ...
        free_.kick(0.5 * double(dt), step_params_.gravity);
        free_.drift(double(dt));
      }
      if (moving_colliders_) pose_colliders(time_ + dt);
      positions_time_ = time_ + dt;
      start_step(end_pending, contact_view());
      if (contact_) exec_.mark_flags(ContactLists<Exec>::kFlagEvent);
      compute_forces(fusion_);
      if (!free_.empty()) {  // ... the particles' reaction at the new state, half kick
        react_and_touch();
        free_.kick(0.5 * double(dt), step_params_.gravity);
      }
      end_pending = fusion_.steps_meet;
      if (!end_pending) end_step();
      time_ += dt;
      ++step_;
    }
    if (end_pending) end_step();
    exec_.flush_stats();
    if (halo_.active()) {
      exec_.synchronize();
      step_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  }

  // A step's position update, with the step before's velocity update in the same pass where that
  // was left pending (IntegrationFusion::steps_meet).
  void start_step(bool after_pending_end, const ContactView& c) {
    if (after_pending_end)
      launch_velocity_then_position_update(exec_, particles(), bonds(), materials_, step_params_, c,
                                           fusion_.gravity, fusion_.init);
    else
      launch_position_update(exec_, particles(), bonds(), materials_, step_params_, c, fusion_.init);
  }

  // A step's velocity update (with gravity, where the run fuses it).
  void end_step() { launch_velocity_update(exec_, particles(), step_params_, fusion_.gravity); }

  std::vector<Collider> colliders() override {
    std::vector<Collider> now = colliders_host_;
    free_.pose(now);  // (the free bodies' full-step velocities; the kernels saw the half-step ones)
    return now;
  }

  // This rank's part of a partitioned run (PartitionedEngine::rank_stats).
  std::vector<SetupStage> setup_stages() const override { return setup_stages_; }

  RankStats local_rank_stats() const {
    RankStats r;
    r.particles = owned_;
    r.ghosts = state_.n - owned_;
    r.bonds = family_.bonds;
    r.step_seconds = step_seconds_;
    r.halo_seconds = halo_.seconds();
    r.halo_bytes = halo_.bytes_sent();
    r.halo_exchanges = halo_.exchanges();
    r.interior = interior_;
    std::snprintf(r.halo_transport, sizeof(r.halo_transport), "%s", halo_.transport());
    r.overlapped = overlap_ ? 1 : 0;
    return r;
  }

  void read_state(ParticleState& out) override { state_.read_frame(out); }

  void read_bonds(BondLists& out) override { download_bonds(state_, out); }

  // The slots' broken bits as the previous call left them, on the backend; the slots whose bit
  // changed since are the flipped ones.
  void bond_changes(size_t slots, BondChanges& out) override {
    if (!take_bond_changes(slots, out)) changed_bits_.download(out.flipped);
  }

  // Copies into a slot of page-locked memory on a stream of their own (frame_reads.h); read at
  // once while every slot is out.
  std::unique_ptr<FrameRead> read_frame(size_t slots, bool changes) override {
    const size_t words = (state_.neighbor.size() + 31) / 32;
    FrameLayout layout = frame_layout(state_.frame_fields(), changes, changes ? words : 0);
    auto slot = frame_slots_->take(exec_, layout.bytes);
    if (!slot) return Engine::read_frame(slots, changes);
    std::vector<HostCopy> copies;
    for (size_t k = 0; k < layout.fields.size(); ++k) {
      const FrameField& f = layout.fields[k];
      copies.push_back({static_cast<char*>(slot->host) + layout.offset[k], f.data, f.count * f.bytes});
    }
    if (changes && !take_bond_changes(slots, layout.whole))
      copies.push_back({static_cast<char*>(slot->host) + layout.flipped_offset, changed_bits_.data(),
                        words * sizeof(uint32_t)});
    copies.erase(std::remove_if(copies.begin(), copies.end(), [](const HostCopy& c) { return c.bytes == 0; }),
                 copies.end());
    exec_.read_back(copies.data(), int(copies.size()), slot->done);
    return std::make_unique<SlotFrameRead<Exec>>(frame_slots_, std::move(slot), std::move(layout));
  }

  int64_t broken_bonds() override { return reduce_broken_bonds(exec_, bonds(), state_.intact.data()); }

  Energy energy() override {
    if (contact_) refresh_contacts();
    Energy e = reduce_energy(exec_, particles(), bonds(), contact_view(), materials_, step_params_, contact_);
    if (features_.ghosts)
      e.strain += reduce_ghost_energy(exec_, particles(), bonds(), ghost_view(), materials_);
    return e;
  }

  int64_t first_non_finite() override {
    if (reduce_non_finite(exec_, particles()) == 0) return -1;
    ParticleState s;
    read_state(s);
    for (int32_t i = 0; i < owned_; ++i)
      if (!is_finite(s.disp[i]) || !is_finite(s.vel[i]) || !is_finite(s.force[i])) return i;
    return -1;
  }

  size_t memory_bytes() const override { return mem_.bytes(); }
  SurfaceGhostCounts surface_ghosts() const override { return ghost_counts_; }
  int64_t force_passes() const override { return force_passes_; }
  int64_t screened_passes() const override { return screened_passes_; }
  int64_t graphed_steps() const override { return graphed_steps_; }
  double critical_time_step() const override { return critical_dt_; }
  void restore_particles(const EngineSnapshot& in) override {
    state_.upload_saved_particles(in);
    free_.restore(in.free_bodies);
    step_ = in.step;
    time_ = in.time;
    positions_time_ = time_;
    motion_.apply(time_, step_params_);
    pose_colliders(time_);
    contacts_.invalidate();
  }
  void set_time_step(double dt) override {
    step_params_.dt = real(dt);
    if constexpr (Exec::kGraphs) exec_.drop_graphs();  // their launches hold the old dt
    contacts_.invalidate();                            // its skin's reach follows dt
  }

  void save(EngineSnapshot& out) override {
    out.step = step_;
    out.time = time_;
    state_.save(out);
    out.free_bodies = free_.saved();
  }

  void restore(const EngineSnapshot& in) override { restore_state(in, nullptr); }

  // A partitioned rank's part of the collective calls (cuda/parallel/partitioned_engine.h).
  int32_t owned() const { return owned_; }
  // Each own particle's energy terms, in local order.
  std::vector<Energy> owned_energies() {
    if (contact_) refresh_contacts();
    auto terms = mem_.template make<Energy>(size_t(owned_));
    const ArrayView<Energy> out = view_of(terms);
    const ParticlesView p = particles();
    const BondsView b = bonds();
    const ContactView c = contact_view();
    const MaterialTable mt = materials_;
    const StepParams sp = step_params_;
    const bool contact = contact_;
    exec_.parallel_for("stats/energy_terms", owned_, [=] PD_HD(int64_t i) {
      out[i] = particle_energy(int32_t(i), p, b, c, mt, sp, contact);
    });
    std::vector<Energy> host;
    terms.download(host);
    mem_.drop(terms);
    return host;
  }
  // The sum of the whole run's terms, in global order, as `energy` adds one rank's.
  Energy sum_energies(const std::vector<Energy>& terms) {
    auto all = mem_.make_from(terms);
    const ArrayView<const Energy> in = view_of(all);
    const Energy total = exec_.template reduce_sum<Energy>("stats/energy", int64_t(terms.size()),
                                                           [=] PD_HD(int64_t i) { return in[i]; });
    mem_.drop(all);
    return total;
  }
  // A restore whose plastic mirror (the partners' history, not all held here) comes with it.
  void restore_with_mirror(const EngineSnapshot& in, const std::vector<real>& plastic_mirror) {
    restore_state(in, &plastic_mirror);
  }

 private:
  // restore's work: the plastic mirror uploaded where it comes with the snapshot, else derived
  // from the history.
  void restore_state(const EngineSnapshot& in, const std::vector<real>* plastic_mirror) {
    state_.check_sizes(in);
    free_.restore(in.free_bodies);
    if (!lattice_.empty()) refresh_lattice_after_restore(state_, in.neighbor, lattice_);
    step_ = in.step;
    time_ = in.time;
    positions_time_ = time_;
    motion_.apply(time_, step_params_);
    pose_colliders(time_);
    state_.upload_saved(in);
    if (!lattice_.empty()) lattice_.intact.upload(lattice_.tables.intact);
    if (features_.plastic) {
      if (plastic_mirror)
        state_.plastic_mirror.upload(*plastic_mirror);
      else
        launch_mirror_plastic(exec_, bonds());
    }
    if (features_.ghosts) launch_ghost_liveness(exec_, bonds(), ghost_view());
    contacts_.invalidate();
  }

  // bond_changes' first part: the bonds whole into `out` when the reader's slots are not the
  // engine's (or on the first call), then the broken bits brought to now on the backend, the
  // changed ones in changed_bits_. False when the reader wants changed_bits_.
  bool take_bond_changes(size_t slots, BondChanges& out) {
    const size_t words = (state_.neighbor.size() + 31) / 32;
    out.whole = broken_bits_.size() != words || slots != state_.neighbor.size();
    if (broken_bits_.size() != words) {
      broken_bits_ = mem_.template make<uint32_t>(words);
      changed_bits_ = mem_.template make<uint32_t>(words);
    }
    if (out.whole) read_bonds(out.bonds);
    launch_broken_bits(exec_, ArrayView<const int32_t>(view_of(state_.neighbor)), view_of(broken_bits_),
                       view_of(changed_bits_));
    return out.whole;
  }

  // The particles the kernels of a step run over: all, or a partitioned rank's own.
  ParticlesView particles() const {
    ParticlesView p = state_.particles();
    p.n = owned_;
    return p;
  }
  BondsView bonds() const {
    BondsView b = state_.bonds();
    b.n = held_;  // (not a partitioned rank's contact ghosts: the lattice masks' stride)
    b.lattice = lattice_.view();
    return b;
  }
  // The contact lists' view, or an empty one in a run without contact.
  ContactView contact_view() {
    return contact_ ? contacts_.view(exec_, step_params_.dt, positions_time_) : ContactView{};
  }

  // Set-up of the surface correction (before the state-based weighted volumes, which take the
  // bonds' factors): the factors from the families as built, before cuts (on a
  // partitioned rank its ghosts' from their owners: a bond's factor takes both ends'), then
  // each bond's at its slot.
  void set_up_surface_correction() {
    state_.allocate(mem_, kSlots, state_.neighbor.size(), FieldNeeds{false, false, false, false, true});
    fill(mem_, state_.surface_factor, Vec3{1, 1, 1});
    fill(mem_, state_.surface_bond, uint16_t(kSurfaceBondOne));
    for (int round = 0; round < kSurfaceCorrectionRounds; ++round) {
      launch_surface_factor(exec_, particles(), bonds(), materials_, round);
      if (halo_.active()) halo_.exchange(state_.surface_factor);
      launch_surface_bond_factors(exec_, particles(), bonds(), materials_);
    }
  }

  // The ghost surface correction's tables (cuda/engine/surface_ghosts.h) from the families as
  // built, before cuts, and their sizes after (`cut_count`), with the scattered bodies' `solids`
  // where the host knows them; `rate` gets the ghost bonds' share of each particle's stability rate.
  void set_up_ghosts(const ParticleSet& ps, const BodySolids* solids, const BondLists& uncut,
                     const std::vector<int32_t>& cut_count, std::vector<double>& rate) {
    GhostTables t = pd::surface_ghosts(ps, materials_, uncut, cut_count, solids);
    check_ghost_memory(t, int64_t(state_.neighbor.size()), backend());
    surface_ghosts_.particle = mem_.make_from(t.particle);
    surface_ghosts_.of = mem_.make_from(t.of);
    surface_ghosts_.inverse = mem_.make_from(t.inverse);
    surface_ghosts_.moment = mem_.make_from(t.moment);
    surface_ghosts_.inv_mw = mem_.make_from(t.inv_mw);
    surface_ghosts_.first = mem_.make_from(t.first);
    surface_ghosts_.offset = mem_.make_from(t.offset);
    surface_ghosts_.receivers = mem_.make_from(t.receivers);
    surface_ghosts_.push_first = mem_.make_from(t.push_first);
    surface_ghosts_.mirror = mem_.template make<int32_t>(state_.neighbor.size());
    surface_ghosts_.pull = mem_.template make_zeroed<real>(size_t(t.size()) * kGhostPull);
    surface_ghosts_.push = mem_.template make_zeroed<Vec4>(size_t(t.push_first.back()));
    surface_ghosts_.live = mem_.template make_zeroed<uint8_t>(size_t(t.size()));
    ghost_counts_ = {t.size(), t.thin, t.precracked, t.linear};
    rate = std::move(t.stability_rate);
    launch_ghost_mirror(exec_, bonds(), ghost_view(), owned_, surface_ghosts_.mirror.data());
    launch_ghost_liveness(exec_, bonds(), ghost_view());
  }

  GhostView ghost_view() const {
    GhostView v;
    v.n = int32_t(surface_ghosts_.particle.size());
    v.particle = view_of(surface_ghosts_.particle);
    v.of = view_of(surface_ghosts_.of);
    v.inverse = view_of(surface_ghosts_.inverse);
    v.moment = view_of(surface_ghosts_.moment);
    v.inv_mw = view_of(surface_ghosts_.inv_mw);
    v.first = view_of(surface_ghosts_.first);
    v.offset = view_of(surface_ghosts_.offset);
    v.receivers = view_of(surface_ghosts_.receivers);
    v.push_first = view_of(surface_ghosts_.push_first);
    v.mirror = view_of(surface_ghosts_.mirror);
    v.pull = view_of(surface_ghosts_.pull);
    v.push = view_of(surface_ghosts_.push);
    v.live = view_of(surface_ghosts_.live);
    return v;
  }

  // State-based set-up: the weighted volumes m from the families as built, and for plastic
  // materials the per-bond history (zero).
  void set_up_state_based() {
    launch_weighted_volume(exec_, particles(), bonds(), materials_);
    state_.allocate(mem_, kSlots, state_.neighbor.size(), FieldNeeds{true, features_.plastic, false});
  }

  // The free colliders' reaction from the particles (summed over the ranks of a partitioned run,
  // in rank order on rank 0 and sent to all, so every rank moves the bodies alike) and from the
  // other colliders.
  void react_and_touch() {
    free_.set_reactions(reactions_.reduce(exec_, particles(), step_params_));
    if (world_ && world_->size() > 1) {
      const std::vector<Wrench> mine = free_.reactions();
      std::vector<char> bytes(mine.size() * sizeof(Wrench));
      std::memcpy(bytes.data(), mine.data(), bytes.size());
      std::vector<std::vector<char>> all;
      world_->gather(bytes, all, 0);
      std::vector<Wrench> sum(mine.size());
      if (world_->rank() == 0)
        for (const std::vector<char>& rank : all)
          for (size_t k = 0; k < sum.size(); ++k) {
            Wrench w;
            std::memcpy(&w, rank.data() + k * sizeof(Wrench), sizeof(Wrench));
            sum[k] = sum[k] + w;
          }
      world_->broadcast(sum.data(), sum.size() * sizeof(Wrench), 0);
      free_.set_reactions(sum);
    }
    free_.touch(colliders_host_, double(step_params_.dt), {grids_host_.data(), &probes_});
  }

  // The colliders' poses at time t, on the backend (their view in the step parameters).
  void pose_colliders(double t) {
    if (colliders_host_.empty()) return;
    motion_.pose_colliders(t, colliders_host_);
    free_.pose(colliders_host_);
    colliders_.upload(colliders_host_);
    spheres_host_.resize(colliders_host_.size());
    for (size_t k = 0; k < colliders_host_.size(); ++k) {
      const Collider& c = colliders_host_[k];
      spheres_host_[k] = with_w(c.center, c.bound > 0 ? c.bound : real(-1));
    }
    collider_spheres_.upload(spheres_host_);
    // The grid, into its device array (grown to twice what it needs when it no longer fits).
    const ColliderGridView g = ColliderGrid::build(colliders_host_, largest_particle_, grid_lists_host_);
    if (grid_lists_host_.size() > collider_grid_lists_.size())
      collider_grid_lists_ = mem_.template make<int32_t>(2 * grid_lists_host_.size());
    exec_.upload(collider_grid_lists_.data(), grid_lists_host_.data(),
                 grid_lists_host_.size() * sizeof(int32_t));
    step_params_.collider_grid = g;
    step_params_.collider_grid.lists = {collider_grid_lists_.data(), int64_t(grid_lists_host_.size())};
  }

  // Kernels 1-5: the forces at the current positions; without `fused`'s init and gravity, which
  // the integration kernels around it then run (IntegrationFusion).
  void compute_forces(const IntegrationFusion& fused = {}) {
    const ParticlesView p = particles();
    const BondsView b = bonds();
    // On a partitioned rank, the ghosts' positions before `init` sums dilatations over partners
    // (state-based), and what `springforces` reads of a partner (strain limit, dilatation,
    // damage) after it, each while the interior particles' part runs.
    const auto init = [&](ParticleRange r) {
      launch_init(exec_, p, b, materials_, features_, r, listed_in(r), bond_threads_);
    };
    if (features_.state_based)
      with_halo(init, state_.disp);
    else if (!fused.init)
      init(all_particles(p));
    if (features_.ghosts) {
      launch_ghost_fit(exec_, p, b, ghost_view(), materials_, ghost_threads_);
      launch_ghost_push(exec_, p, b, ghost_view(), materials_, ghost_threads_);
    }
    if (features_.plastic) launch_plasticity(exec_, p, materials_);
    const auto springforces = [&](ParticleRange r) { queue_springforces(p, b, r); };
    if (features_.state_based)
      with_halo(springforces, state_.disp, state_.state);
    else
      with_halo(springforces, state_.disp);
    if (features_.ghosts) {
      launch_ghost_forces(exec_, p, b, ghost_view(), ghost_threads_);
      launch_ghost_drops(exec_, p, b, ghost_view(), materials_);
    }
    take_broke_flags();
    // (After a contact build that brought in contact ghosts the state may have moved: the views
    // are taken again.)
    if (contact_) {  // after springforces is queued: waiting for position_update's flag idles nothing
      if (refresh_contacts())
        launch_collisions(exec_, particles(), contact_view(), materials_, step_params_.contact_stiffness);
    }
    if (body_forces_ && !fused.gravity) launch_bodyforces(exec_, particles(), step_params_);
  }

  // `launch` over the own particles with the ghosts' `fields` brought up to date first: on a
  // partitioned rank the interior particles' part (they read no ghost) runs while the halo
  // travels, then the boundary's.
  template <class Launch, class... T>
  void with_halo(const Launch& launch, DeviceArray<T, Exec>&... fields) {
    if (!halo_.active()) return launch(ParticleRange{0, owned_, balanced_ids_.data()});
    halo_.start(fields...);
    if (overlap_) launch(ParticleRange{0, interior_});
    halo_.finish();
    launch(overlap_ ? ParticleRange{interior_, owned_ - interior_} : ParticleRange{0, owned_});
  }

  // The contact lists at the current positions (ContactLists::refresh); on a partitioned rank
  // with the contact ghosts gathered first, their skins from their velocities.
  bool refresh_contacts() {
    if (!halo_.active())
      return contacts_.refresh(mem_, particles(), materials_, step_params_.dt, positions_time_);
    return contacts_.refresh(mem_, particles(), materials_, step_params_.dt, positions_time_, world_, [&] {
      halo_.exchange(state_.vel);
      ghosts_.gather(mem_, state_, halo_, contacts_.reach());
      return state_.particles();
    });
  }

  // Kernel 4 in the form chosen from the pass before the last (bond_screen.h), over `r`; the
  // pass's flag is read by take_broke_flags once the whole pass is queued, and the host waits
  // only for the pass before, not for what the device still runs.
  // (While a graph is captured, in the graph's form.)
  void queue_springforces(const ParticlesView& p, const BondsView& b, ParticleRange r) {
    const bool screened = capturing_ ? pass_screened_ : screen_next_pass();
    const int parity = int(flag_units_ % kBrokeFlags);
    launch_springforces(exec_, p, b, materials_, features_, r, listed_in(r), screened,
                        exec_.flag(kFlagBroke + parity), bond_threads_);
    pass_screened_ = screened;
  }

  bool screen_next_pass() const {
    return screen_ == BondScreen::kAlways || (screen_ == BondScreen::kAuto && breaking_hold_ == 0);
  }

  // The lattice particles of r whose stencil is `listed` (a partitioned rank's that read their
  // partners from their lists), as a range of the ids of all of them.
  ParticleRange listed_in(ParticleRange r) const {
    const std::vector<int32_t>& ids = lattice_.listed_host;
    const auto lo = std::lower_bound(ids.begin(), ids.end(), r.first);
    const auto hi = std::lower_bound(lo, ids.end(), r.first + r.count);
    return {int32_t(lo - ids.begin()), int32_t(hi - lo), lattice_.listed_ids.data()};
  }

  // After a force pass, or a graph of `passes` (whose passes raise one flag): marks its flag and
  // reads the one of the pass or graph before it. (Nothing while a graph is captured.)
  void take_broke_flags(int passes = 1) {
    if (capturing_) return;
    const int parity = int(flag_units_ % kBrokeFlags);
    exec_.mark_flags(kBrokeFlagEvent + parity);
    screened_passes_ += pass_screened_ ? passes : 0;
    force_passes_ += passes;
    if (flag_units_++ == 0) return;
    const int last = int((flag_units_ - 2) % kBrokeFlags);
    const bool broke = exec_.take_flags(1u << (kFlagBroke + last), kBrokeFlagEvent + last) != 0;
    breaking_hold_ = broke ? kScreenHoldPasses : std::max(breaking_hold_ - passes, 0);
  }

  // kGraphSteps steps as one graph launch (step_graphs.h), in the form the next pass would take;
  // the graph of that form and flag parity is recorded the first time it is needed. The steps'
  // host work is only the clock's.
  void run_step_graph() {
    if constexpr (Exec::kGraphs) {
      const bool screened = screen_next_pass();
      const int slot = 2 * int(screened) + int(flag_units_ % kBrokeFlags);
      pass_screened_ = screened;
      if (!exec_.has_graph(slot)) record_step_graph(slot);
      exec_.launch_graph(slot, kStepGraphStat);
      for (int k = 0; k < kGraphSteps; ++k) time_ += step_params_.dt;
      positions_time_ = time_;
      step_params_.time = real(time_);
      step_ += kGraphSteps;
      graphed_steps_ += kGraphSteps;
      take_broke_flags(kGraphSteps);
    }
  }

  void record_step_graph(int slot) {
    if constexpr (Exec::kGraphs) {
      capturing_ = true;
      exec_.begin_capture();
      try {
        for (int k = 0; k < kGraphSteps; ++k) {
          start_step(k > 0 && fusion_.steps_meet, ContactView{});
          compute_forces(fusion_);
          if (!fusion_.steps_meet || k == kGraphSteps - 1) end_step();
        }
      } catch (...) {
        exec_.abort_capture();
        capturing_ = false;
        throw;
      }
      capturing_ = false;
      exec_.end_capture(slot);
    }
  }

  // Exec flag events: the contact flags' (ContactLists), and one per parity of the force
  // passes' broke flags.
  static constexpr int kBrokeFlagEvent = 1;
  static_assert(ContactLists<Exec>::kFlagEvent < kBrokeFlagEvent &&
                kBrokeFlagEvent + kBrokeFlags <= Exec::kFlagEvents &&
                kFlagBroke + kBrokeFlags <= Exec::kFlags);

  KernelStats stats_;
  Exec exec_;
  // The ghost surface correction's tables (set_up_ghosts), and its counts: ghosted particles,
  // and those left without ghosts (thin families, pre-cracks).
  struct GhostArrays {
    DeviceArray<int32_t, Exec> particle, of, first, receivers, push_first, mirror;
    DeviceArray<real, Exec> inverse, moment, inv_mw, pull;
    DeviceArray<Vec4, Exec> offset, push;
    DeviceArray<uint8_t, Exec> live;
  } surface_ghosts_;
  SurfaceGhostCounts ghost_counts_;
  DeviceMemory<Exec> mem_;
  std::string device_;
  MaterialTable materials_;
  StepParams step_params_;
  MotionScript motion_;
  bool scripted_motion_ = !motion_.empty();
  std::vector<Collider> colliders_host_;
  bool moving_colliders_ = motion_.colliders_move();
  FreeBodies free_{motion_.colliders};
  ColliderReactions<Exec> reactions_;  // the particles' reaction on the free bodies
  DeviceArray<Collider, Exec> colliders_;
  std::vector<Vec4> spheres_host_;  // the colliders' bounding spheres, and on the backend
  DeviceArray<Vec4, Exec> collider_spheres_;
  real largest_particle_ = 0;             // V^(1/3) of the largest particle
  std::vector<int32_t> grid_lists_host_;  // the colliders' grid (collider_grid.h), and on the backend
  DeviceArray<int32_t, Exec> collider_grid_lists_;
  std::vector<float> grids_host_;  // the mesh colliders' distance grids, and on the backend
  DeviceArray<float, Exec> collider_grids_;
  std::vector<std::vector<Vec3>> probes_;  // the meshes' probe points (body_contact.h)
  bool contact_ = false;
  BondScreen screen_ = BondScreen::kAuto;
  int bond_threads_ = 1;   // per particle in the GPU's bond loops (cuda/team.h)
  int ghost_threads_ = 1;  // per ghosted particle in the ghost kernels (team.h ghost_threads_for)
  // The order of the bond loops' team launches over explicit families (balanced_particle_order;
  // empty: by index).
  DeviceArray<int32_t, Exec> balanced_ids_;
  int64_t force_passes_ = 0, screened_passes_ = 0;
  int64_t flag_units_ = 0;  // force passes and graphs of passes queued (their broke flags' parity)
  bool graphs_ = false;     // the step as graphs of kGraphSteps steps (step_graphs.h)
  bool capturing_ = false;  // a graph is being recorded: no host work between the launches
  int64_t graphed_steps_ = 0;
  DeviceArray<uint32_t, Exec> broken_bits_, changed_bits_;  // bond_changes' bits
  std::shared_ptr<FrameReadSlots<Exec>> frame_slots_ = std::make_shared<FrameReadSlots<Exec>>();
  int breaking_hold_ = 0;       // passes left to run with the breaking pass
  bool pass_screened_ = false;  // the form of the pass being queued
  KernelFeatures features_;
  bool body_forces_ = false;
  IntegrationFusion fusion_;  // (kernels 1 and 5 in the integration kernels where the run allows)
  int64_t step_ = 0;
  double time_ = 0;
  // The time of the positions the kernels see: time_, or within a step of `advance` the step's end
  // from its position update on (the contact lists' frame is a function of it).
  double positions_time_ = 0;
  double critical_dt_ = 0;
  FamilyStats family_;
  int32_t owned_ = 0;        // particles the step kernels run over (ParticlesView::n)
  int32_t interior_ = 0;     // of which the first read no ghost (a partitioned rank's)
  int32_t held_ = 0;         // particles with a place in the families (BondsView::n): own and bond ghosts
  bool overlap_ = true;      // a partitioned rank runs the interior part while the halo travels
  double step_seconds_ = 0;  // a partitioned rank's wall time in `advance`
  // Set-up's stages: the time since the last stage ended, the device's queued work done.
  void end_stage(const char* name) {
    exec_.synchronize();
    const auto now = std::chrono::steady_clock::now();
    setup_stages_.push_back({name, std::chrono::duration<double>(now - stage_start_).count()});
    stage_start_ = now;
  }
  std::chrono::steady_clock::time_point stage_start_;
  std::vector<SetupStage> setup_stages_;

  Halo<Exec> halo_;  // a partitioned rank's ghost refresh (inactive otherwise)
  ContactGhosts<Exec> ghosts_;
  Comm* world_ = nullptr;

  EngineState<Exec> state_;
  LatticeState<Exec> lattice_;
  ContactLists<Exec> contacts_;
};

}  // namespace pd
