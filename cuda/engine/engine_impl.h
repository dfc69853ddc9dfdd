// The engine for one backend: owns the particle, bond and hash buffers in the backend's
// memory and runs the step as the sequence of the seven kernels. Included by
// host/engine_cpu.cpp (CpuExec) and cuda/engine_cuda.cu (CudaExec).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "cuda/device_array.h"
#include "cuda/engine/bond_cuts.h"
#include "cuda/engine/engine.h"
#include "cuda/engine/lattice_families.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/launch.h"

namespace pd {

inline uint32_t hash_bins_for(int64_t n) {
  uint32_t bins = 1024;
  while (bins < 2 * n && bins < (1u << 30)) bins <<= 1;
  return bins;
}

template <class Exec>
class EngineImpl final : public Engine {
 public:
  EngineImpl(const SimulationInput& in, std::string device)
      : exec_(&stats_),
        device_(std::move(device)),
        materials_(in.materials),
        step_params_(in.step),
        motion_(in.motion),
        contact_(in.contact),
        screen_(in.screen) {
    features_ = features_of(materials_, contact_);
    const ParticleSet& ps = in.particles;
    n_ = int32_t(ps.size());
    if (n_ <= 0) throw std::runtime_error("the scene has no particles");
    upload_particles(ps);
    build_families();
    if (!in.cuts.empty()) apply_cuts(in);
    if (in.lattice_families) build_lattice_families(in.particles);
    compute_critical_time_step();
    if (features_.state_based) allocate_state();
    if (contact_) allocate_contacts();
    body_forces_ = step_params_.n_projectiles > 0 || step_params_.gravity.x != 0 ||
                   step_params_.gravity.y != 0 || step_params_.gravity.z != 0;
    motion_.apply(time_, step_params_);
    compute_forces();
    exec_.flush_stats();
  }

  Backend backend() const override { return Exec::kDevice ? Backend::kCuda : Backend::kCpu; }
  std::string device_name() const override { return device_; }
  const FamilyStats& family_stats() const override { return family_; }
  int64_t step() const override { return step_; }
  double time() const override { return time_; }
  KernelStats& stats() override { return stats_; }

  void advance(int64_t steps) override {
    const real dt = step_params_.dt;
    for (int64_t s = 0; s < steps; ++s) {
      step_params_.time = real(time_ + dt);
      if (scripted_motion_) motion_.apply(time_ + dt, step_params_);
      launch_position_update(exec_, particles(), step_params_, contact_ ? contact_view() : ContactView{});
      if (contact_) exec_.mark_flags(kContactFlagEvent);
      compute_forces();
      launch_velocity_update(exec_, particles(), step_params_);
      time_ += dt;
      ++step_;
    }
    exec_.flush_stats();
  }

  void read_state(ParticleState& out) override {
    std::vector<Vec4> disp;
    disp_.download(disp);
    out.disp.resize(disp.size());
    for (size_t i = 0; i < disp.size(); ++i) out.disp[i] = xyz(disp[i]);
    vel_.download(out.vel);
    force_.download(out.force);
    intact_.download(out.intact);
  }

  void read_bonds(BondLists& out) override {
    slice_offset_.download(out.slice_offset);
    count_.download(out.count);
    neighbor_.download(out.neighbor);
  }

  int64_t broken_bonds() override { return reduce_broken_bonds(exec_, bonds(), intact_.data()); }

  Energy energy() override {
    if (contact_) refresh_contacts();
    return reduce_energy(exec_, particles(), bonds(), contact_ ? contact_view() : ContactView{}, materials_,
                         step_params_, contact_);
  }

  int64_t first_non_finite() override {
    if (reduce_non_finite(exec_, particles()) == 0) return -1;
    ParticleState s;
    read_state(s);
    for (int32_t i = 0; i < n_; ++i)
      if (!is_finite(s.disp[i]) || !is_finite(s.vel[i]) || !is_finite(s.force[i])) return i;
    return -1;
  }

  size_t memory_bytes() const override { return allocated_; }
  int64_t force_passes() const override { return force_passes_; }
  int64_t screened_passes() const override { return screened_passes_; }
  double critical_time_step() const override { return critical_dt_; }

  void save(EngineSnapshot& out) override {
    out.step = step_;
    out.time = time_;
    for_each_state_array(out, [](const char*, auto& array, auto& host) { array.download(host); });
  }

  void restore(const EngineSnapshot& in) override {
    auto& snapshot = const_cast<EngineSnapshot&>(in);  // only read below
    for_each_state_array(snapshot, [](const char* what, auto& array, auto& host) {
      if (host.size() != array.size())
        throw std::invalid_argument(std::string("snapshot ") + what + " has " + std::to_string(host.size()) +
                                    " entries, the engine " + std::to_string(array.size()));
    });
    if (!lattice_.stencils.empty()) {  // the intact bits follow the restored families
      BondLists lists;                 // the layout as built, the partners as restored
      slice_offset_.download(lists.slice_offset);
      count_.download(lists.count);
      lists.neighbor = in.neighbor;
      refresh_lattice_intact(lattice_, lists);
    }
    step_ = in.step;
    time_ = in.time;
    motion_.apply(time_, step_params_);
    for_each_state_array(snapshot, [](const char*, auto& array, auto& host) { array.upload(host); });
    if (!lattice_.stencils.empty()) lattice_intact_.upload(lattice_.intact);
    if (features_.plastic) launch_mirror_plastic(exec_, bonds());
    contacts_built_ = false;  // built again from the restored positions
  }

 private:
  template <class T>
  DeviceArray<T, Exec> make(size_t n) {
    allocated_ += n * sizeof(T);
    return DeviceArray<T, Exec>(&exec_, n);
  }
  template <class T>
  DeviceArray<T, Exec> make_from(const std::vector<T>& host) {
    auto a = make<T>(host.size());
    a.upload(host);
    return a;
  }

  ParticlesView particles() const {
    ParticlesView p;
    p.n = n_;
    p.rest = rest_.data();
    p.disp = disp_.data();
    p.vel = vel_.data();
    p.force = force_.data();
    p.inv_mass = inv_mass_.data();
    p.material = material_.data();
    p.body = body_.data();
    p.flags = flags_.data();
    p.anchor = anchor_.data();
    p.strain_limit0 = strain_limit0_.data();
    p.strain_min = strain_min_.data();
    p.intact = intact_.data();
    p.ledger = ledger_.data();
    p.state = state_.data();
    return p;
  }

  BondsView bonds() const {
    BondsView b;
    b.n = n_;
    b.slice_offset = slice_offset_.data();
    b.count = count_.data();
    b.neighbor = neighbor_.data();
    b.plastic = plastic_ext_.data();
    b.plastic_mirror = plastic_mirror_.data();
    b.strength = bond_strength_.data();
    b.lattice.words = lattice_.words;
    b.lattice.stencil = lattice_stencil_.data();
    b.lattice.stencils = stencils_.data();
    b.lattice.entries = stencil_entries_.data();
    b.lattice.present = lattice_present_.data();
    b.lattice.intact = lattice_intact_.data();
    b.lattice.weak = lattice_weak_.data();
    return b;
  }

  HashView hash_view(bool sorted) const {
    HashView h;
    h.bins = bins_;
    h.inv_cell = inv_cell_;
    h.key = sorted ? key_sorted_.data() : key_.data();
    h.sorted = sorted ? ids_sorted_.data() : ids_.data();
    h.bin_start = bin_start_.data();
    h.bin_end = bin_end_.data();
    h.record = sorted ? record_.data() : nullptr;
    return h;
  }

  void upload_particles(const ParticleSet& ps) {
    std::vector<Vec4> rest(n_), disp(n_);
    for (int32_t i = 0; i < n_; ++i) {
      rest[i] = with_w(ps.rest[i], ps.volume[i]);
      disp[i] = {0, 0, 0, ps.strain_limit0[i]};
    }
    rest_ = make_from(rest);
    disp_ = make_from(disp);
    vel_ = make_from(ps.velocity);
    force_ = make<Vec3>(n_);
    force_.zero();
    std::vector<real> inv_mass(ps.mass.size());
    for (size_t i = 0; i < inv_mass.size(); ++i) inv_mass[i] = real(1) / ps.mass[i];
    inv_mass_ = make_from(inv_mass);
    material_ = make_from(ps.material);
    body_ = make_from(ps.body);
    flags_ = make_from(ps.flags);
    anchor_ = ps.anchor.size() == ps.size() ? make_from(ps.anchor) : make<uint8_t>(n_);
    if (ps.anchor.size() != ps.size()) anchor_.zero();
    strain_limit0_ = make_from(ps.strain_limit0);
    strain_min_ = make<real>(n_);
    strain_min_.zero();
    intact_ = make<int32_t>(n_);
    ledger_ = make<Ledger>(n_);
    ledger_.zero();
  }

  // Hash buffers sized for n particles with cells of side `cell`.
  void allocate_hash(real cell) {
    bins_ = hash_bins_for(n_);
    inv_cell_ = real(1) / cell;
    key_ = make<uint32_t>(n_);
    key_sorted_ = make<uint32_t>(n_);
    ids_ = make<int32_t>(n_);
    ids_sorted_ = make<int32_t>(n_);
    bin_start_ = make<int32_t>(bins_);
    bin_end_ = make<int32_t>(bins_);
  }

  // Contact lists (kernels/collisions.h): the hash they are built from, with cells twice the
  // reach of two particles at rest (contact distance plus their skins), its sorted records, and
  // the lists.
  void allocate_contacts() {
    real spacing = 0;
    for (int m = 0; m < materials_.count; ++m) spacing = std::max(spacing, materials_.m[m].contact_spacing);
    const double contact_distance = 0.5 * double(spacing);
    contact_quarter_max_ = real(0.25) * spacing;
    contact_rest_skin_ = real(kContactRestSkin * contact_distance);
    contact_skin_cap_ = real(kContactSkinCap * contact_distance);
    allocate_hash(real(2 * (contact_distance + 2 * double(contact_rest_skin_))));
    record_ = make<Vec4>(n_);
    contact_origin_ = make<Vec4>(n_);
    contact_count_ = make<int32_t>(n_);
    contact_partner_ = make<int32_t>(size_t(kContactCapacity) * size_t(n_));
  }

  ContactView contact_view() {
    ContactView c;
    c.n = n_;
    c.capacity = int32_t(contact_partner_.size() / size_t(n_));
    c.base = contact_rest_skin_;
    c.per_speed = real(double(step_params_.dt) * kContactStepsAhead / kContactTrigger);
    c.cap = contact_skin_cap_;
    c.count = contact_count_.data();
    c.partner = contact_partner_.data();
    c.origin = contact_origin_.data();
    c.moved = exec_.flag(kFlagMoved);
    return c;
  }

  // Builds the contact lists at the current positions if a particle has left its skin since
  // the last build (position_update raised the flag), or if there are none yet. A list that
  // overflows its room doubles the room of all and builds again.
  void refresh_contacts() {
    const bool moved = exec_.take_flags(kContactFlagMask, kContactFlagEvent) & (1u << kFlagMoved);
    if (contacts_built_ && !moved) return;
    const ParticlesView p = particles();
    launch_reset_bins(exec_, "pd/collection_reset", hash_view(true));
    launch_collection<true>(exec_, "pd/collection", p, hash_view(false), hash_view(true), materials_);
    for (;;) {
      launch_build_contacts(exec_, p, hash_view(true), contact_view(), materials_, contact_quarter_max_,
                            exec_.flag(kFlagOverflow), exec_.flag(kFlagPairs));
      exec_.mark_flags(kContactFlagEvent);
      const uint32_t raised = exec_.take_flags(kContactFlagMask, kContactFlagEvent);
      contact_pairs_ = raised & (1u << kFlagPairs);
      if (!(raised & (1u << kFlagOverflow))) break;
      const size_t room = contact_partner_.size() * 2;
      drop(contact_partner_);
      contact_partner_ = make<int32_t>(room);
    }
    contacts_built_ = true;
  }

  template <class T>
  void drop(DeviceArray<T, Exec>& a) {
    allocated_ -= a.bytes();
    a = DeviceArray<T, Exec>();
  }

  void release_hash() {
    drop(key_);
    drop(key_sorted_);
    drop(ids_);
    drop(ids_sorted_);
    drop(bin_start_);
    drop(bin_end_);
    drop(record_);
    bins_ = 0;
  }

  void build_families() {
    real horizon = 0;
    for (int m = 0; m < materials_.count; ++m) horizon = std::max(horizon, materials_.m[m].family_radius());
    allocate_hash(real(horizon * (1.0 + 2 * kHorizonSlack)));
    const ParticlesView p = particles();
    launch_reset_bins(exec_, "family/reset", hash_view(true));
    launch_collection<false>(exec_, "family/collection", p, hash_view(false), hash_view(true));

    count_ = make<int32_t>(n_);
    launch_count_family(exec_, p, hash_view(true), materials_, count_.data());
    const int64_t slices = (int64_t(n_) + kSliceWidth - 1) / kSliceWidth;
    auto length = make<int64_t>(slices);
    slice_offset_ = make<int64_t>(slices + 1);
    launch_slice_length(exec_, n_, count_.data(), length.data());
    const int64_t slots = exec_.exclusive_scan(length.data(), slice_offset_.data(), slices);
    exec_.upload(slice_offset_.data() + slices, &slots, sizeof(int64_t));
    drop(length);

    check_bond_memory(slots);
    neighbor_ = make<int32_t>(size_t(std::max<int64_t>(slots, 1)));
    neighbor_.zero();
    launch_fill_family(exec_, p, hash_view(true), materials_, bonds());
    release_hash();

    std::vector<int32_t> counts;
    count_.download(counts);
    family_.slots = slots;
    count_family_stats(counts);
    intact_.upload(counts);
  }

  void count_family_stats(const std::vector<int32_t>& counts) {
    family_.min = *std::min_element(counts.begin(), counts.end());
    family_.max = *std::max_element(counts.begin(), counts.end());
    family_.bonds = 0;
    for (int32_t c : counts) family_.bonds += c;
    family_.mean = double(family_.bonds) / n_;
  }

  // Pre-cracks and weakened surfaces: bonds crossing them leave the families (compacted on the
  // host) or keep a strength factor, before anything is derived from the families.
  void apply_cuts(const SimulationInput& in) {
    BondLists lists;
    read_bonds(lists);
    std::vector<uint8_t> strength;
    family_.cuts = cut_bonds(in.cuts, in.particles.rest, in.particles.body, lists, strength);
    neighbor_.upload(lists.neighbor);
    count_.upload(lists.count);
    intact_.upload(lists.count);
    count_family_stats(lists.count);
    if (strength.empty()) return;
    bond_strength_ = make_from(strength);
    features_.weak_bonds = true;
  }

  // Box-grid bodies find their partners by offset (host/lattice_families.h); the host keeps
  // the tables to check and refresh the intact bits of a restored snapshot.
  void build_lattice_families(const ParticleSet& ps) {
    BondLists lists;
    read_bonds(lists);
    lattice_ = lattice_families(ps, materials_, lists);
    family_.lattice_particles = lattice_.particles();
    if (lattice_.stencils.empty()) return;
    features_.lattice = true;
    lattice_stencil_ = make_from(lattice_.stencil);
    stencils_ = make_from(lattice_.stencils);
    stencil_entries_ = make_from(lattice_.entries);
    lattice_present_ = make_from(lattice_.present);
    lattice_intact_ = make_from(lattice_.intact);
    if (!features_.weak_bonds) return;
    std::vector<uint8_t> strength;
    bond_strength_.download(strength);
    mark_weak_lattice_bonds(lattice_, lists, strength);
    lattice_weak_ = make_from(lattice_.weak);
  }

  // The arrays a run changes, paired with their snapshot vectors (save, restore).
  template <class F>
  void for_each_state_array(EngineSnapshot& s, F f) {
    f("disp", disp_, s.disp);
    f("vel", vel_, s.vel);
    f("force", force_, s.force);
    f("strain_min", strain_min_, s.strain_min);
    f("intact", intact_, s.intact);
    f("ledger", ledger_, s.ledger);
    f("state", state_, s.state);
    f("neighbor", neighbor_, s.neighbor);
    f("plastic", plastic_ext_, s.plastic);
  }

  // Smallest stable step over the particles, from the families as built.
  void compute_critical_time_step() {
    auto rate = make<double>(size_t(n_));
    launch_stability_rate(exec_, particles(), bonds(), materials_, rate.data());
    std::vector<double> host;
    rate.download(host);
    drop(rate);
    const double fastest = *std::max_element(host.begin(), host.end());
    critical_dt_ = fastest > 0 ? std::sqrt(2.0 / fastest) : std::numeric_limits<double>::infinity();
  }

  // The bond arrays are the bulk of the memory: refused with a clear message, before they are
  // allocated, when the backend has not enough free.
  void check_bond_memory(int64_t slots) const {
    const double per_slot = sizeof(int32_t) + (features_.plastic ? 2 * sizeof(real) : 0);
    const double need = double(slots) * per_slot;
    const double free = double(backend_available_bytes(backend()));
    if (need <= free) return;
    throw ResourceError("the families hold " + std::to_string(slots) + " bond slots (" + std::to_string(n_) +
                        " particles), which need " + format_bytes(need) + " of " +
                        (Exec::kDevice ? "GPU" : "host") + " memory; " + format_bytes(free) +
                        " are free. Lower --scale, the horizon or the particle count" +
                        (Exec::kDevice ? ", or run on a GPU with more memory" : ""));
  }

  // State-based arrays: the (theta, m, phi) records, m computed once, and for plasticity
  // the per-bond plastic extension and its mirror at the partner's slot.
  void allocate_state() {
    state_ = make<Vec4>(n_);
    state_.zero();
    launch_weighted_volume(exec_, particles(), bonds(), materials_);
    if (!features_.plastic) return;
    plastic_ext_ = make<real>(neighbor_.size());
    plastic_ext_.zero();
    plastic_mirror_ = make<real>(neighbor_.size());
    plastic_mirror_.zero();
  }

  // Kernels 1-5: the forces at the current positions.
  void compute_forces() {
    const ParticlesView p = particles();
    const BondsView b = bonds();
    launch_init(exec_, p, b, materials_, features_);
    if (features_.plastic) launch_plasticity(exec_, p, materials_);
    queue_springforces(p, b);
    if (contact_) {  // after springforces is queued: waiting for position_update's flag idles nothing
      refresh_contacts();
      if (contact_pairs_)
        launch_collisions(exec_, p, contact_view(), materials_, step_params_.contact_stiffness);
    }
    if (body_forces_) launch_bodyforces(exec_, p, step_params_);
  }

  // Kernel 4 in the form chosen from the pass before the last (bond_screen.h): that pass's
  // flag is read after this one is queued, so the host waits for nothing the device still runs.
  void queue_springforces(const ParticlesView& p, const BondsView& b) {
    const bool screened =
        screen_ == BondScreen::kAlways || (screen_ == BondScreen::kAuto && breaking_hold_ == 0);
    const int parity = int(force_passes_ % kBrokeFlags);
    launch_springforces(exec_, p, b, materials_, features_, screened, exec_.flag(kFlagBroke + parity));
    exec_.mark_flags(kBrokeFlagEvent + parity);
    screened_passes_ += screened;
    if (force_passes_++ == 0) return;
    const int last = int((force_passes_ - 2) % kBrokeFlags);
    const bool broke = exec_.take_flags(1u << (kFlagBroke + last), kBrokeFlagEvent + last) != 0;
    breaking_hold_ = broke ? kScreenHoldPasses : std::max(breaking_hold_ - 1, 0);
  }

  // Exec flag events: the contact flags', and one per parity of the force passes' broke flags.
  static constexpr int kContactFlagEvent = 0, kBrokeFlagEvent = 1;
  static_assert(kBrokeFlagEvent + kBrokeFlags <= Exec::kFlagEvents &&
                kFlagBroke + kBrokeFlags <= Exec::kFlags);

  KernelStats stats_;
  Exec exec_;
  std::string device_;
  MaterialTable materials_;
  StepParams step_params_;
  MotionScript motion_;
  bool scripted_motion_ = !motion_.empty();
  bool contact_ = false;
  BondScreen screen_ = BondScreen::kAuto;
  int64_t force_passes_ = 0, screened_passes_ = 0;
  int breaking_hold_ = 0;  // passes left to run with the breaking pass
  KernelFeatures features_;
  bool body_forces_ = false;
  int32_t n_ = 0;
  int64_t step_ = 0;
  double time_ = 0;
  size_t allocated_ = 0;
  double critical_dt_ = 0;
  FamilyStats family_;

  DeviceArray<Vec4, Exec> rest_, disp_, state_;
  DeviceArray<Vec3, Exec> vel_, force_;
  DeviceArray<real, Exec> inv_mass_, strain_limit0_, strain_min_;
  DeviceArray<uint16_t, Exec> material_;
  DeviceArray<int32_t, Exec> body_, intact_;
  DeviceArray<Ledger, Exec> ledger_;
  DeviceArray<uint8_t, Exec> flags_, anchor_;

  DeviceArray<int64_t, Exec> slice_offset_;
  DeviceArray<int32_t, Exec> count_, neighbor_;
  DeviceArray<real, Exec> plastic_ext_, plastic_mirror_;
  DeviceArray<uint8_t, Exec> bond_strength_;
  LatticeFamilies lattice_;
  DeviceArray<int16_t, Exec> lattice_stencil_;
  DeviceArray<Stencil, Exec> stencils_;
  DeviceArray<StencilEntry, Exec> stencil_entries_;
  DeviceArray<uint32_t, Exec> lattice_present_, lattice_intact_, lattice_weak_;

  uint32_t bins_ = 0;
  real inv_cell_ = 0;
  DeviceArray<uint32_t, Exec> key_, key_sorted_;
  DeviceArray<int32_t, Exec> ids_, ids_sorted_, bin_start_, bin_end_;
  DeviceArray<Vec4, Exec> record_;  // contact lists: sorted records for the build

  real contact_quarter_max_ = 0, contact_rest_skin_ = 0, contact_skin_cap_ = 0;
  bool contacts_built_ = false;
  bool contact_pairs_ = false;  // some list is not empty
  DeviceArray<Vec4, Exec> contact_origin_;
  DeviceArray<int32_t, Exec> contact_count_, contact_partner_;
};

}  // namespace pd
