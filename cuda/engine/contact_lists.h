// Contact lists (cuda/kernels/collisions.h): per particle, the particles within its contact
// reach plus both skins, rebuilt whenever a particle has left its skin since its list's build
// (position_update raises the flag and names the movers): where few did, their lists alone
// (contact_relist.h), else every list through a spatial hash over current positions. The skins
// are kept in a frame chosen at each full build, at rest or moving with the particles
// (contact_frame.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>

#include "cuda/engine/device_memory.h"
#include "cuda/engine/spatial_hash.h"
#include "cuda/launch.h"
#include "cuda/parallel/comm.h"

namespace pd {

template <class Exec>
class ContactLists {
 public:
  // Exec flag event the contact flags are read through.
  static constexpr int kFlagEvent = 0;
  // Movers a round may rebuild alone (at least; n / 512 where more), relistings between two full
  // builds (at least; n / 8), and pairs (partner, mover) a round may link per mover it keeps.
  static constexpr int32_t kMovers = 256;
  static constexpr int32_t kRelistings = 4096;
  static constexpr int32_t kLinksPerMover = 8;

  // The hash they are built from, with cells twice the reach of two particles at rest (contact
  // distance plus their skins), its sorted records, and the lists.
  // incremental: the movers' lists rebuilt alone where they can be (the forces are the same).
  // gravity: the acceleration every free particle shares (the moving frame's).
  void allocate(DeviceMemory<Exec>& mem, int32_t n, const MaterialTable& materials, bool incremental = true,
                Vec3 gravity = {0, 0, 0}) {
    n_ = n;
    gravity_ = {double(gravity.x), double(gravity.y), double(gravity.z)};
    real spacing = 0;
    for (int m = 0; m < materials.count; ++m) spacing = std::max(spacing, materials.m[m].contact_spacing);
    const double contact_distance = 0.5 * double(spacing);
    quarter_max_ = real(0.25) * spacing;
    rest_skin_ = real(kContactRestSkin * contact_distance);
    skin_cap_ = real(kContactSkinCap * contact_distance);
    cell_ = real(2 * (contact_distance + 2 * double(rest_skin_)));
    reach_ = contact_distance + 2 * double(skin_cap_);
    size_lists(mem, n, kContactCapacity);
    incremental_ = incremental;
    const int32_t movers = std::max(kMovers, n / 512), nodes = std::max(kRelistings, n / 8);
    movers_ = mem.template make<int32_t>(size_t(movers));
    counters_ = mem.template make_zeroed<int32_t>(3);
    node_id_ = mem.template make<int32_t>(size_t(nodes));
    node_next_ = mem.template make<int32_t>(size_t(nodes));
    node_round_ = mem.template make<int32_t>(size_t(nodes));
    node_record_ = mem.template make<Vec4>(size_t(nodes));
    node_skin_ = mem.template make<real>(size_t(nodes));
    link_ = mem.template make<int32_t>(2 * size_t(kLinksPerMover) * size_t(movers));
  }

  // The farthest two particles can be and still be listed: the largest contact distance plus two
  // of the largest skins (a partitioned run's contact ghosts lie within it of a rank's own).
  double reach() const { return reach_; }

  // The lists' view for positions at time `now` (the frame's shift since the full build).
  ContactView view(Exec& exec, real dt, double now) const {
    ContactView c;
    c.n = n_;
    c.capacity = int32_t(partner_.size() / size_t(n_));
    c.base = rest_skin_;
    c.per_speed = real(double(dt) * kContactStepsAhead / kContactTrigger);
    c.cap = skin_cap_;
    c.count = view_of(count_);
    c.partner = view_of(partner_);
    c.origin = view_of(origin_);
    c.moved = exec.flag(kFlagMoved);
    c.movers = view_of(movers_);
    c.mover_count = counters_.data();
    c.crowded = exec.flag(kFlagCrowded);
    const double tau = now - built_at_;
    const auto shift = [&](size_t a) {
      return real(frame_velocity_[a] * tau + 0.5 * frame_acceleration_[a] * tau * tau);
    };
    const auto velocity = [&](size_t a) { return real(frame_velocity_[a] + frame_acceleration_[a] * tau); };
    c.shift = {shift(0), shift(1), shift(2)};
    c.frame_velocity = {velocity(0), velocity(1), velocity(2)};
    return c;
  }

  // Builds the lists at the current positions (those of time `now`) if a particle has left its
  // skin since its list's build, or if there are none yet: the movers' alone where that can be
  // done (relist), else all, in the frame that keeps them longer (choose_frame). A list that
  // overflows its room doubles the room of all and builds again. Returns whether some list is not
  // empty (else `collisions` need not run).
  // In a partitioned run (`world` given) every rank builds when any particle has moved, and
  // `gather_ghosts` first brings in the other ranks' particles within reach, returning the view of
  // every particle the rank then holds: the lists are built over them all, in the frame at rest.
  bool refresh(DeviceMemory<Exec>& mem, ParticlesView p, const MaterialTable& materials, real dt, double now,
               Comm* world = nullptr, const std::function<ParticlesView()>& gather_ghosts = {}) {
    Exec& exec = mem.exec();
    const uint32_t raised_by_moves = exec.take_flags(kContactFlagMask, kFlagEvent);
    bool moved = raised_by_moves & (1u << kFlagMoved);
    if (world) moved = world->bit_or(moved) != 0;
    if (built_ && !moved) return pairs_;
    // More movers than a round keeps (a body in free fall moves all at once): straight to the full
    // build, without the round that would find as much.
    const bool crowded = raised_by_moves & (1u << kFlagCrowded);
    if (built_ && incremental_ && !world && !crowded && relist(exec, p, materials, dt, now)) return pairs_;
    if (gather_ghosts) {
      p = gather_ghosts();
      if (p.n != n_) size_lists(mem, p.n, room_);
    }
    choose_frame(exec, p, world == nullptr);
    built_at_ = now;
    launch_reset_bins(exec, "pd/collection_reset", hash_.view(true));
    launch_collection<true>(exec, "pd/collection", p, hash_.view(false), hash_.view(true), materials);
    for (;;) {
      launch_build_contacts(exec, p, hash_.view(true), view(exec, dt, now), materials, quarter_max_,
                            exec.flag(kFlagOverflow), exec.flag(kFlagPairs));
      exec.mark_flags(kFlagEvent);
      const uint32_t raised = exec.take_flags(kContactFlagMask, kFlagEvent);
      pairs_ = raised & (1u << kFlagPairs);
      if (!(raised & (1u << kFlagOverflow))) break;
      const size_t room = partner_.size() * 2;
      mem.drop(partner_);
      partner_ = mem.template make<int32_t>(room);
      room_ *= 2;
    }
    if (incremental_) {  // no particle relisted: every bin empty (-1)
      launch_clear_relisted(exec, relist_view());
      exec.fill_bytes(relist_head_.data(), 0xff, relist_head_.bytes());
    }
    counters_.zero();
    built_ = true;
    return pairs_;
  }

  // The hash and lists for n particles with room for `capacity` partners each. A partitioned
  // rank's count changes at almost every build while fragments fly (its contact ghosts come and
  // go), so the buffers are kept while they hold n particles and grown with room for 1/16 more,
  // rather than freed and allocated anew at each build (gigabytes at 20M particles).
  void size_lists(DeviceMemory<Exec>& mem, int32_t n, int32_t capacity) {
    n_ = n;
    capacity = std::max(capacity, 1);
    if (n <= rows_ && capacity <= room_) return;
    const int64_t rows = rows_ == 0 ? n : std::min<int64_t>(int64_t(n) + std::max(n / 16, 1024), INT32_MAX);
    hash_.release(mem);
    mem.drop(origin_);
    mem.drop(count_);
    mem.drop(partner_);
    mem.drop(relist_entry_);
    mem.drop(relist_claimed_);
    mem.drop(relist_head_);
    rows_ = int32_t(rows);
    room_ = capacity;
    hash_.allocate(mem, rows_, cell_);
    hash_.record = mem.template make<Vec4>(size_t(rows_));
    origin_ = mem.template make<Vec4>(size_t(rows_));
    count_ = mem.template make<int32_t>(size_t(rows_));
    partner_ = mem.template make<int32_t>(size_t(room_) * size_t(rows_));
    relist_entry_ = mem.template make_zeroed<int32_t>(size_t(rows_));
    relist_claimed_ = mem.template make_zeroed<int32_t>(size_t(rows_));
    relist_head_ = mem.template make<int32_t>(hash_.bins);
  }

  // The lists are built again from the next positions (after a restore).
  void invalidate() { built_ = false; }
  bool pairs() const { return pairs_; }

 private:
  // The movers' lists rebuilt alone (contact_relist.h), the movers and the pairs linked cleared
  // for the next round; false where that cannot be done (more relistings than kept, a list past
  // its room): then all are built.
  bool relist(Exec& exec, ParticlesView p, const MaterialTable& materials, real dt, double now) {
    ++round_;
    launch_relist_contacts(exec, p, hash_.view(true), view(exec, dt, now), relist_view(), materials,
                           quarter_max_, round_, exec.flag(kFlagOverflow), exec.flag(kFlagPairs));
    exec.fill_bytes(counters_.data(), 0, 2 * sizeof(int32_t));
    exec.mark_flags(kFlagEvent);
    const uint32_t raised = exec.take_flags(kContactFlagMask, kFlagEvent);
    if (raised & (1u << kFlagOverflow)) return false;
    pairs_ = pairs_ || (raised & (1u << kFlagPairs));
    return true;
  }

  // The frame of the lists about to be built (contact_frame.h): moving with the particles' mean
  // velocity and the gravity where they move together (`may_move`: a run of one rank; a
  // partitioned run keeps the frame at rest, which its ranks need not agree on), else at rest.
  void choose_frame(Exec& exec, const ParticlesView& p, bool may_move) {
    frame_velocity_ = {0, 0, 0};
    frame_acceleration_ = {0, 0, 0};
    if (!may_move || p.n == 0) return;
    const VelocityMoments m = reduce_velocity_moments(exec, p);
    if (!moving_frame_wins(m, p.n)) return;
    frame_velocity_ = {m.x / p.n, m.y / p.n, m.z / p.n};
    frame_acceleration_ = gravity_;
  }

  RelistView relist_view() const {
    RelistView r;
    r.entry = view_of(relist_entry_);
    r.claimed = view_of(relist_claimed_);
    r.head = view_of(relist_head_);
    r.id = view_of(node_id_);
    r.next = view_of(node_next_);
    r.round = view_of(node_round_);
    r.record = view_of(node_record_);
    r.skin = view_of(node_skin_);
    r.link = view_of(link_);
    r.links = counters_.data() + 1;
    r.nodes = counters_.data() + 2;
    return r;
  }

  int32_t n_ = 0;     // particles the lists are for
  int32_t rows_ = 0;  // particles the buffers hold (at least n_)
  int32_t room_ = 0;  // partners each list has room for (partner_ holds room_ x rows_)
  SpatialHash<Exec> hash_;
  real quarter_max_ = 0, rest_skin_ = 0, skin_cap_ = 0, cell_ = 0;
  double reach_ = 0;
  bool built_ = false;
  bool pairs_ = false;  // some list is not empty
  // The lists' frame: velocity and acceleration at the last full build (zero: at rest), its time.
  std::array<double, 3> frame_velocity_{}, frame_acceleration_{}, gravity_{};
  double built_at_ = 0;
  bool incremental_ = true;
  int32_t round_ = 0;  // rounds of relisting so far
  DeviceArray<Vec4, Exec> origin_;
  DeviceArray<int32_t, Exec> count_, partner_;
  // The movers of this round; counters_: movers counted, pairs linked, relisted nodes taken.
  DeviceArray<int32_t, Exec> movers_, counters_;
  // RelistView: per particle (two), per hash bin, per node, and the pairs to link.
  DeviceArray<int32_t, Exec> relist_entry_, relist_claimed_, relist_head_, node_id_, node_next_, node_round_,
      link_;
  DeviceArray<Vec4, Exec> node_record_;
  DeviceArray<real, Exec> node_skin_;
};

}  // namespace pd
