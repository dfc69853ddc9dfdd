// The particles' reaction on every free collider in one go: the particles within reach of a free
// collider (its bounding sphere, found through the colliders' grid, collider_grid.h) are counted, the counts
// scanned into places, each such particle's reaction on each such collider written to its place, and the
// short list summed on the host in particle order (so the sums are the same on every backend and thread
// count). Two passes over the particles and a scan whatever the number of free colliders, where a reduction
// over all the particles for each collider cost about 0.1 ms apiece at 1M particles (bench/REPORT.md).
#pragma once

#include <vector>

#include "cuda/engine/device_memory.h"
#include "cuda/kernels/colliders.h"

namespace pd {

// One particle's reaction on one free collider (its place in the list of free colliders).
struct ReactionPart {
  Wrench wrench;
  int32_t body = 0;
};

template <class Exec>
class ColliderReactions {
 public:
  ColliderReactions() = default;
  // For `particles` particles and the free colliders `bodies` (collider indices, in FreeBodies order).
  ColliderReactions(DeviceMemory<Exec>& mem, int64_t particles, const std::vector<int32_t>& bodies,
                    size_t colliders)
      : mem_(&mem),
        slots_(mem.make_from(body_slots(bodies, colliders))),
        counts_(mem.template make<int64_t>(size_t(particles))),
        places_(mem.template make<int64_t>(size_t(particles))),
        bodies_(bodies.size()) {}

  // Each free collider's reaction from the particles of `p` at the current state (after `bodyforces`).
  std::vector<Wrench> reduce(Exec& ex, const ParticlesView& p, const StepParams& sp) {
    const ArrayView<const int32_t> slots = view_of(slots_);
    const ArrayView<int64_t> counts = view_of(counts_), places = view_of(places_);
    ex.parallel_for("pd/collider_reaction_count", p.n, [=] PD_HD(int64_t i) {
      int64_t n = 0;
      for_free_in_reach(i, p, sp, slots, [&](int32_t, int32_t) { ++n; });
      counts[i] = n;
    });
    const int64_t total = ex.exclusive_scan(counts_.data(), places_.data(), p.n);
    std::vector<Wrench> sums(bodies_);
    if (total == 0) return sums;
    if (size_t(total) > parts_.size()) {
      mem_->drop(parts_);
      parts_ = mem_->template make<ReactionPart>(2 * size_t(total));
    }
    const ArrayView<ReactionPart> parts = view_of(parts_);
    ex.parallel_for("pd/collider_reaction", p.n, [=] PD_HD(int64_t i) {
      if (counts[i] == 0) return;
      int64_t at = places[i];
      for_free_in_reach(i, p, sp, slots, [&](int32_t k, int32_t body) {
        parts[at++] = {collider_reaction(int32_t(i), p, sp.colliders[k], sp.dt, sp.collider_grids.data()),
                       body};
      });
    });
    host_.resize(size_t(total));
    ex.download(host_.data(), parts_.data(), size_t(total) * sizeof(ReactionPart));
    for (const ReactionPart& part : host_) sums[size_t(part.body)] = sums[size_t(part.body)] + part.wrench;
    return sums;
  }

 private:
  // Per collider: its place among the free ones, or -1.
  static std::vector<int32_t> body_slots(const std::vector<int32_t>& bodies, size_t colliders) {
    std::vector<int32_t> slots(colliders, -1);
    for (size_t b = 0; b < bodies.size(); ++b) slots[size_t(bodies[b])] = int32_t(b);
    return slots;
  }

  // f(collider, body slot) for each free collider particle i is within reach of: the candidates of
  // i's cell of the colliders' grid, then those without a bounding radius (set up by hand).
  template <class F>
  PD_HD static void for_free_in_reach(int64_t i, const ParticlesView& p, const StepParams& sp,
                                      ArrayView<const int32_t> slots, F f) {
    const ColliderGridView& g = sp.collider_grid;
    const Vec3 x = p.position(int32_t(i));
    const real size = std::cbrt(p.volume(int32_t(i)));
    auto visit = [&](int32_t k) {
      const int32_t body = slots[k];
      if (body < 0) return;
      const Vec4 sphere = sp.collider_spheres[k];
      if (!out_of_reach(x, size, xyz(sphere), sphere.w)) f(k, body);
    };
    const Vec3 q = g.inv_cell * (x - g.lo);
    const real top = real(g.dims);
    if (q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < top && q.y < top && q.z < top) {
      const int32_t cell = (int32_t(q.z) * g.dims + int32_t(q.y)) * g.dims + int32_t(q.x);
      for (int32_t j = g.lists[cell]; j < g.lists[cell + 1]; ++j) visit(g.lists[j]);
    }
    for (int64_t j = g.unbounded; j < g.lists.size; ++j) visit(g.lists[j]);
  }

  DeviceMemory<Exec>* mem_ = nullptr;
  DeviceArray<int32_t, Exec> slots_;
  DeviceArray<int64_t, Exec> counts_, places_;
  DeviceArray<ReactionPart, Exec> parts_;  // grown to twice what a step needs when it no longer fits
  std::vector<ReactionPart> host_;
  size_t bodies_ = 0;
};

}  // namespace pd
