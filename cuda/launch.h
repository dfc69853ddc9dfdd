// Launchers: each wraps one kernel body in the backend's parallel_for, under the name the
// profiler reports. Views and parameters are captured by value. One source for both backends.
#pragma once

#include <initializer_list>
#include <string>
#include <type_traits>
#include <utility>

#include "cuda/features.h"
#include "cuda/kernels/bodyforces.h"
#include "cuda/kernels/collection.h"
#include "cuda/kernels/collisions.h"
#include "cuda/kernels/contact_frame.h"
#include "cuda/kernels/contact_relist.h"
#include "cuda/kernels/energy.h"
#include "cuda/kernels/family.h"
#include "cuda/kernels/init.h"
#include "cuda/kernels/integrate.h"
#include "cuda/kernels/integrate_fused.h"
#include "cuda/kernels/plasticity.h"
#include "cuda/kernels/springforces.h"
#include "cuda/kernels/springforces_state.h"
#include "cuda/kernels/surface_ghosts.h"

namespace pd {

// The statistics name of one instantiation of a kernel: its name and, in brackets, the
// features it was compiled for (those set), e.g. "pd/springforces[state,plastic,lattice]".
// Registers and occupancy differ per instantiation, so each is timed and described apart.
inline std::string kernel_variant(const char* kernel,
                                  std::initializer_list<std::pair<const char*, bool>> flags) {
  std::string name = kernel, set;
  for (const auto& [flag, on] : flags)
    if (on) set += (set.empty() ? "" : ",") + std::string(flag);
  return set.empty() ? name : name + "[" + set + "]";
}

// The particles a launch runs over: [first, first + count) of the view's (a partitioned rank
// runs the force kernels over its interior particles while the halo travels, then over the rest),
// or where `ids` is set the particles ids[first], ..., ids[first + count - 1]. `skip_listed`
// leaves out the lattice particles whose stencil is `listed`: a partitioned rank runs the rest
// in one rank's lattice loop (partners at offsets) and those in a launch of their own.
struct ParticleRange {
  int32_t first = 0, count = 0;
  const int32_t* ids = nullptr;
  bool skip_listed = false;
};
inline ParticleRange all_particles(const ParticlesView& p) {
  return {0, p.n};
}

// The particle of launch index t over range r, or -1 where r leaves it out.
PD_HD inline int32_t range_particle(const ParticleRange& r, int64_t t, const BondsView& b) {
  const int32_t i = r.ids ? r.ids[t] : int32_t(t);
  if (r.skip_listed) {
    const int32_t s = b.lattice.stencil[i];
    if (s >= 0 && b.lattice.stencils[s].listed) return -1;
  }
  return i;
}

// A partitioned rank's lattice particles (f.lattice_listed) in two launches: those at the rank's
// offsets in one rank's loop over r, the listed ones skipped, then those that read their partners
// from their lists (`listed_ids`: their ids within r) in the loop that tests the stencil per bond.
// One loop serving both ran 20% slower per GPU than one rank's (bench/NOTES.md); each particle's
// sums are the same either way. Elsewhere one launch over r. launch(features, range).
template <class Launch>
void launch_listed_apart(KernelFeatures f, ParticleRange r, ParticleRange listed_ids, const Launch& launch) {
  if (!(f.lattice && f.lattice_listed)) return launch(f, r);
  KernelFeatures offsets = f;
  offsets.lattice_listed = false;
  r.skip_listed = true;
  launch(offsets, r);
  if (listed_ids.count > 0) launch(f, listed_ids);
}

// A kernel over range r, one thread per particle (kThreads = 1) or a team of kThreads per particle
// (team.h, GPU only): body(i, team) for each particle i of r.
template <int kThreads, int kMinBlocks = 0, class Exec, class Body>
void launch_over_range(Exec& ex, const char* name, ParticleRange r, const BondsView& b, const Body& body) {
  if constexpr (kThreads == 1) {
    ex.template parallel_for_from<kMinBlocks>(name, r.first, r.count, [=] PD_HD(int64_t t) {
      const int32_t i = range_particle(r, t, b);
      if (i >= 0) body(i, Team<1>{});
    });
  } else {
    ex.template parallel_for_team<kThreads, kMinBlocks>(name, r.first, r.count,
                                                        [=] PD_HD(int64_t t, const Team<kThreads>& team) {
                                                          const int32_t i = range_particle(r, t, b);
                                                          if (i >= 0) body(i, team);
                                                        });
  }
}

// Calls f(std::integral_constant<int, k>) for the launch's threads per particle k (1, or on the
// GPU one of the team sizes of team.h), so each count is its own instantiation.
template <class Exec, class F>
void with_bond_threads(int threads, F&& f) {
  if constexpr (Exec::kDevice) {
    switch (threads) {
      case 32:
        return f(std::integral_constant<int, 32>{});
      case 16:
        return f(std::integral_constant<int, 16>{});
      case 8:
        return f(std::integral_constant<int, 8>{});
      case 4:
        return f(std::integral_constant<int, 4>{});
      default:
        break;
    }
  }
  f(std::integral_constant<int, 1>{});
}

// The kernel-name flag of a team of kThreads lanes ("team8"); one thread has none.
template <int kThreads>
constexpr const char* team_flag() {
  switch (kThreads) {
    case 32:
      return "team32";
    case 16:
      return "team16";
    case 8:
      return "team8";
    default:
      return "team4";
  }
}

// Kernel 1.
template <bool kStateBased, bool kAnisotropic, int kLattice, bool kPlastic, int kThreads, class Exec>
void launch_init_variant(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, ParticleRange r) {
  static const std::string name = kernel_variant("pd/init", {{"state", kStateBased},
                                                             {"aniso", kAnisotropic},
                                                             {"lattice", kLattice == kLatticeOffsets},
                                                             {"lattice-listed", kLattice == kLatticeListed},
                                                             {"plastic", kPlastic},
                                                             {team_flag<kThreads>(), kThreads > 1}});
  launch_over_range<kThreads>(ex, name.c_str(), r, b, [=] PD_HD(int32_t i, const Team<kThreads>& team) {
    init_particle<kStateBased, kAnisotropic, kLattice, kPlastic>(i, p, b, mt, team);
  });
}

// `listed_ids`: on a partitioned rank with lattice families, the particles of r whose stencil is
// `listed` (launch_listed_apart). `threads`: per particle in the bond loops (team.h).
template <class Exec>
void launch_init(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, KernelFeatures f, ParticleRange r,
                 ParticleRange listed_ids = {}, int threads = 1) {
  if (!f.state_based) return launch_init_variant<false, false, kNoLattice, false, 1>(ex, p, b, mt, r);
  with_bond_threads<Exec>(threads, [&](auto team) {
    constexpr int kThreads = decltype(team)::value;
    launch_listed_apart(f, r, listed_ids, [&](const KernelFeatures& g, ParticleRange q) {
      static_bools(
          [&](auto anisotropic, auto lattice, auto listed, auto plastic) {
            constexpr bool kLattice = decltype(lattice)::value, kListed = decltype(listed)::value;
            if constexpr (kLattice || !kListed)  // (listed partners only with lattice families)
              launch_init_variant<true, decltype(anisotropic)::value, lattice_mode(kLattice, kListed),
                                  decltype(plastic)::value, kThreads>(ex, p, b, mt, q);
          },
          g.anisotropic, g.lattice, g.lattice && g.lattice_listed, g.plastic);
    });
  });
}

// Kernel 5 (plastic state-based materials): the yield test of the return mapping, after `init`
// summed the trial norm; `springforces` applies it to the bonds.
template <class Exec>
void launch_plasticity(Exec& ex, ParticlesView p, MaterialTable mt) {
  ex.parallel_for("pd/plasticity", p.n, [=] PD_HD(int64_t i) { yield_test(int32_t(i), p, mt); });
}

// Blocks of 256 `ghost_fit`'s team launches keep resident per SM: 4 caps it at 64 registers (96
// unbounded, occupancy 0.25 -> 0.5): the fit 0.39 -> 0.27 ms on Chen's twisted bar at --scale 100
// and 0.42 -> 0.31 ms on the gallery's vase with ghosts, 3 blocks (80 registers) 0.30 / 0.32 (one
// H200, bench/NOTES.md, 2026-11-30). One thread per particle (forced) stays unbounded.
constexpr int kGhostFitBlocks = 4;

// The ghost surface correction (surface_ghosts.h): the fits after `init` and the partners' shares
// pushed, the ghost bonds' forces after `springforces` (`threads` per particle: team.h) and the
// ghosts dropped where a bond broke, each ghosted particle's liveness
// from its bonds (set-up, restore), and the slots' mirror rows (set-up).
template <int kThreads, class Exec>
void launch_ghost_fit_variant(Exec& ex, ParticlesView p, BondsView b, GhostView g, MaterialTable mt) {
  if constexpr (kThreads == 1)
    ex.parallel_for("pd/ghost_fit", g.n, [=] PD_HD(int64_t k) { ghost_fit(int32_t(k), p, b, g, mt); });
  else
    ex.template parallel_for_team<kThreads, kGhostFitBlocks>(
        "pd/ghost_fit", 0, g.n,
        [=] PD_HD(int64_t k, const Team<kThreads>& team) { ghost_fit(int32_t(k), p, b, g, mt, team); });
}
template <int kThreads, class Exec>
void launch_ghost_push_variant(Exec& ex, ParticlesView p, BondsView b, GhostView g, MaterialTable mt) {
  if constexpr (kThreads == 1)
    ex.parallel_for("pd/ghost_push", g.n, [=] PD_HD(int64_t k) { ghost_push(int32_t(k), p, b, g, mt); });
  else
    ex.template parallel_for_team<kThreads>(
        "pd/ghost_push", 0, g.n,
        [=] PD_HD(int64_t k, const Team<kThreads>& team) { ghost_push(int32_t(k), p, b, g, mt, team); });
}
template <int kThreads, class Exec>
void launch_ghost_forces_variant(Exec& ex, ParticlesView p, BondsView b, GhostView g) {
  if constexpr (kThreads == 1)
    ex.parallel_for("pd/ghost_forces", g.receivers.size,
                    [=] PD_HD(int64_t r) { ghost_forces(int32_t(r), p, b, g); });
  else
    ex.template parallel_for_team<kThreads>(
        "pd/ghost_forces", 0, g.receivers.size,
        [=] PD_HD(int64_t r, const Team<kThreads>& team) { ghost_forces(int32_t(r), p, b, g, team); });
}
template <class Exec>
void launch_ghost_fit(Exec& ex, ParticlesView p, BondsView b, GhostView g, MaterialTable mt,
                      int threads = 1) {
  with_bond_threads<Exec>(
      threads, [&](auto lanes) { launch_ghost_fit_variant<decltype(lanes)::value>(ex, p, b, g, mt); });
}
template <class Exec>
void launch_ghost_push(Exec& ex, ParticlesView p, BondsView b, GhostView g, MaterialTable mt,
                       int threads = 1) {
  with_bond_threads<Exec>(
      threads, [&](auto lanes) { launch_ghost_push_variant<decltype(lanes)::value>(ex, p, b, g, mt); });
}
template <class Exec>
void launch_ghost_forces(Exec& ex, ParticlesView p, BondsView b, GhostView g, int threads = 1) {
  with_bond_threads<Exec>(
      threads, [&](auto lanes) { launch_ghost_forces_variant<decltype(lanes)::value>(ex, p, b, g); });
}
template <class Exec>
void launch_ghost_drops(Exec& ex, ParticlesView p, BondsView b, GhostView g, MaterialTable mt) {
  ex.parallel_for("pd/ghost_drops", g.n, [=] PD_HD(int64_t k) { ghost_drops(int32_t(k), p, b, g, mt); });
}
template <class Exec>
void launch_ghost_liveness(Exec& ex, BondsView b, GhostView g) {
  ex.parallel_for("family/ghost_liveness", g.n, [=] PD_HD(int64_t k) { ghost_liveness(int32_t(k), b, g); });
}
template <class Exec>
void launch_ghost_mirror(Exec& ex, BondsView b, GhostView g, int32_t particles, int32_t* mirror) {
  ex.parallel_for("family/ghost_mirror", particles,
                  [=] PD_HD(int64_t i) { ghost_mirror(int32_t(i), b, g, mirror); });
}

template <class Exec>
void launch_ghost_weighted_volume(Exec& ex, ParticlesView p, GhostView g) {
  ex.parallel_for("family/ghost_weighted_volume", g.n,
                  [=] PD_HD(int64_t k) { ghost_weighted_volume(int32_t(k), p, g); });
}
template <class Exec>
double reduce_ghost_energy(Exec& ex, ParticlesView p, BondsView b, GhostView g, MaterialTable mt) {
  return ex.template reduce_sum<double>(
      "stats/ghost_energy", g.n, [=] PD_HD(int64_t k) { return ghost_energy(int32_t(k), p, b, g, mt); });
}

// After a restore: each bond end's e^p copied to its mirror at the partner's slot.
template <class Exec>
void launch_mirror_plastic(Exec& ex, BondsView b) {
  ex.parallel_for("family/mirror_plastic", b.n, [=] PD_HD(int64_t i) { mirror_plastic(int32_t(i), b); });
}

template <class Exec>
void launch_reset_bins(Exec& ex, const char* name, HashView h) {
  ex.parallel_for(name, h.bins, [=] PD_HD(int64_t b) { reset_bin(uint32_t(b), h); });
}

// Kernel 2: bin keys, a stable sort, then bin bounds. kCurrent hashes current positions
// (contact lists) and also writes each sorted entry's record (position, a quarter of the contact
// spacing); otherwise reference positions (family build).
template <bool kCurrent, class Exec>
void launch_collection(Exec& ex, const char* name, ParticlesView p, HashView unsorted, HashView sorted,
                       MaterialTable mt = {}) {
  ex.parallel_for(name, p.n, [=] PD_HD(int64_t i) {
    const Vec3 x = kCurrent ? p.position(int32_t(i)) : xyz(p.rest[i]);
    hash_particle(int32_t(i), x, unsorted);
  });
  ex.sort_by_key("pd/collection_sort", unsorted.key.data(), unsorted.sorted.data(), sorted.key.data(),
                 sorted.sorted.data(), p.n, sorted.bins);
  ex.parallel_for("pd/collection_bins", p.n, [=] PD_HD(int64_t s) {
    mark_bin_bounds(int32_t(s), p.n, sorted);
    if (kCurrent) {  // (not constexpr: an extended lambda cannot first-capture there)
      const int32_t i = sorted.sorted[s];
      sorted.record[s] = with_w(p.position(i), contact_quarter(i, p, mt));
    }
  });
}

// Kernel 2 for contact: the list build's three passes (collisions.h).
template <class Exec>
void launch_build_contacts(Exec& ex, ParticlesView p, HashView h, ContactView c, MaterialTable mt,
                           real quarter_max, int32_t* overflow, int32_t* pairs) {
  ex.parallel_for("pd/contact_build", p.n,
                  [=] PD_HD(int64_t s) { build_contacts(int32_t(s), p, h, c, overflow, pairs); });
  ex.parallel_for("pd/contact_extend", p.n, [=] PD_HD(int64_t i) {
    extend_contacts(int32_t(i), p, h, c, mt, quarter_max, overflow, pairs);
  });
  ex.parallel_for("pd/contact_sort", p.n, [=] PD_HD(int64_t i) { sort_contacts(int32_t(i), p, c); });
}

// Kernel 2 for contact, where few particles left their skins: their lists alone, in five passes
// (contact_relist.h); `rebuild` raised where all must be built instead.
template <class Exec>
void launch_relist_contacts(Exec& ex, ParticlesView p, HashView h, ContactView c, RelistView r,
                            MaterialTable mt, real quarter_max, int32_t round, int32_t* rebuild,
                            int32_t* pairs) {
  // The five passes in one launch (a grid-wide barrier between them on the GPU): a round is
  // launch-bound (tens of movers), and five launches cost it 29 us on the vase (bench/NOTES.md).
  const int64_t movers = c.movers.size, links = r.link.size / 2;
  ex.parallel_phases(
      "pd/contact_relist", {movers, movers * kRelistLanes, movers, links, links},
      [=] PD_HD(int64_t t) { relist_mover(int32_t(t), p, h, c, r, mt, round, rebuild); },
      [=] PD_HD(int64_t g) { gather_mover(int32_t(g), h, c, r, quarter_max); },
      [=] PD_HD(int64_t t) { finish_mover(int32_t(t), p, c, r, round, rebuild, pairs); },
      [=] PD_HD(int64_t q) { add_link(int32_t(q), c, r, rebuild); },
      [=] PD_HD(int64_t q) { sort_linked(int32_t(q), p, c, r); });
}

// The contact lists' frame (contact_frame.h): the particles' velocities and their squares summed.
template <class Exec>
VelocityMoments reduce_velocity_moments(Exec& ex, ParticlesView p) {
  return ex.template reduce_sum<VelocityMoments>(
      "pd/contact_frame", p.n, [=] PD_HD(int64_t i) { return velocity_moments_of(p.vel[i]); });
}

// After a full build of the lists: no particle relisted.
template <class Exec>
void launch_clear_relisted(Exec& ex, RelistView r) {
  ex.parallel_for("pd/contact_relist_clear", r.id.size,
                  [=] PD_HD(int64_t e) { clear_relisted(int32_t(e), r); });
}

// Kernel 3, over the particles' contact lists.
template <class Exec>
void launch_collisions(Exec& ex, ParticlesView p, ContactView c, MaterialTable mt, real stiffness) {
  ex.parallel_for("pd/collisions", p.n,
                  [=] PD_HD(int64_t i) { collision_forces(int32_t(i), p, c, mt, stiffness); });
}

// Kernel 4, one instantiation per feature set so a scene pays only for what it uses, in two
// forms (bond_screen.h): kScreened, the pass without the breaking path. Writes the force (the
// other force kernels add to it) and raises `broke` where a bond broke.
// kSurface: bond-based materials with the surface correction (springforces.h).
template <bool kStateBased, bool kPlastic, bool kAnisotropic, bool kWeak, int kLattice, bool kScreened,
          bool kSurface, int kThreads>
PD_HD inline void springforces_body(int32_t i, const ParticlesView& p, const BondsView& b,
                                    const MaterialTable& mt, int32_t* broke, const Team<kThreads>& team) {
  if constexpr (kStateBased && kScreened)
    screened_state_forces<kPlastic, kAnisotropic, kWeak, kLattice>(i, p, b, mt, broke, team);
  else if constexpr (kStateBased)
    state_forces<kPlastic, kAnisotropic, kWeak, kLattice>(i, p, b, mt, broke, team);
  else if constexpr (kScreened)
    screened_spring_forces<kWeak, kLattice, kSurface>(i, p, b, mt, broke, team);
  else
    spring_forces<kWeak, kLattice, kSurface>(i, p, b, mt, broke, team);
}

// Blocks of 256 a springforces variant keeps resident per SM, which caps its registers (0: no
// bound; bench/NOTES.md). Lattice families, bond-based: with weakened bonds or screened 5 (48
// registers; they would take 55-56 and run 4), the plain breaking pass unbounded (48 either way, 4%
// slower bounded). Families read from their lists wait on their partners' records and hide it with
// more resident warps: bond-based 6 (40 registers), the screened pass of one thread per particle 8
// (32), the weakened bonds' breaking pass 5 (at 40 it lost 11%). State-based 4 (at most 64; on the
// lattice they spill at 48), the screened elastic pass on lists 5 (48 registers: +4%; the plastic
// pass and the breaking pass lose 1-2% there).
template <bool kStateBased, bool kPlastic, bool kWeak, int kLattice, bool kScreened, int kThreads>
constexpr int springforces_min_blocks() {
  const bool listed = kLattice == kNoLattice;
  if (kStateBased) return listed && kScreened && !kPlastic ? 5 : 4;
  if (!listed) return kWeak || kScreened ? 5 : 0;
  if (!kScreened) return kWeak ? 5 : 6;
  return !kWeak && kThreads == 1 ? 8 : 6;
}

template <bool kStateBased, bool kPlastic, bool kAnisotropic, bool kWeak, int kLattice, bool kScreened,
          bool kSurface, int kThreads, class Exec>
void launch_springforces_variant(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, ParticleRange r,
                                 int32_t* broke) {
  constexpr int kMinBlocks =
      springforces_min_blocks<kStateBased, kPlastic, kWeak, kLattice, kScreened, kThreads>();
  static const std::string name =
      kernel_variant("pd/springforces", {{"state", kStateBased},
                                         {"plastic", kPlastic},
                                         {"aniso", kAnisotropic},
                                         {"weak", kWeak},
                                         {"lattice", kLattice == kLatticeOffsets},
                                         {"lattice-listed", kLattice == kLatticeListed},
                                         {"screened", kScreened},
                                         {"surface", kSurface},
                                         {team_flag<kThreads>(), kThreads > 1}});
  launch_over_range<kThreads, kMinBlocks>(
      ex, name.c_str(), r, b, [=] PD_HD(int32_t i, const Team<kThreads>& team) {
        springforces_body<kStateBased, kPlastic, kAnisotropic, kWeak, kLattice, kScreened, kSurface>(
            i, p, b, mt, broke, team);
      });
}

// `listed_ids`: on a partitioned rank with lattice families, the particles of r whose stencil is
// `listed` (launch_listed_apart). `threads`: per particle in the bond loops (team.h).
template <class Exec>
void launch_springforces(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, KernelFeatures f,
                         ParticleRange r, ParticleRange listed_ids, bool screened, int32_t* broke,
                         int threads = 1) {
  with_bond_threads<Exec>(threads, [&](auto team) {
    constexpr int kThreads = decltype(team)::value;
    launch_listed_apart(f, r, listed_ids, [&](const KernelFeatures& g, ParticleRange q) {
      static_bools(
          [&](auto state_based, auto plastic, auto anisotropic, auto weak, auto lattice, auto listed,
              auto screen, auto surface) {
            constexpr bool kState = decltype(state_based)::value;
            constexpr bool kPlastic = kState && decltype(plastic)::value;
            constexpr bool kAniso = kState && decltype(anisotropic)::value;
            constexpr bool kLattice = decltype(lattice)::value, kListed = decltype(listed)::value;
            constexpr bool kSurface = decltype(surface)::value;
            // Plasticity and anisotropy exist only for state-based materials, the surface correction
            // only for bond-based ones, listed partners only with lattice families: no copies for the
            // combinations that cannot occur.
            if constexpr ((kState || (!decltype(plastic)::value && !decltype(anisotropic)::value)) &&
                          !(kState && kSurface) && (kLattice || !kListed))
              launch_springforces_variant<kState, kPlastic, kAniso, decltype(weak)::value,
                                          lattice_mode(kLattice, kListed), decltype(screen)::value, kSurface,
                                          kThreads>(ex, p, b, mt, q, broke);
          },
          g.state_based, g.state_based && g.plastic, g.state_based && g.anisotropic, g.weak_bonds, g.lattice,
          g.lattice && g.lattice_listed, screened, g.surface);
    });
  });
}

// Kernel 5: without projectiles and colliders, the gravity-only instantiation.
template <class Exec>
void launch_bodyforces(Exec& ex, ParticlesView p, StepParams sp) {
  if (sp.n_projectiles > 0 || sp.colliders.size > 0)
    ex.parallel_for("pd/bodyforces", p.n, [=] PD_HD(int64_t i) { body_forces<true>(int32_t(i), p, sp); });
  else
    ex.parallel_for("pd/bodyforces[gravity]", p.n,
                    [=] PD_HD(int64_t i) { body_forces<false>(int32_t(i), p, sp); });
}

// Kernels 6 and 7, each with what the run lets it take on (integrate_fused.h): `with_init`, the
// bond-based `init` after the position update (kernel 1); `with_gravity`, gravity alone before
// the velocity update (kernel 5).
// With contact lists (c.moved set), the position update also reports a particle that left its skin.
template <bool kContact, bool kInit, class Exec>
void launch_position_update_variant(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, StepParams sp,
                                    ContactView c) {
  static const std::string name =
      kernel_variant("pd/position_update", {{"contact", kContact}, {"init", kInit}});
  ex.parallel_for(name.c_str(), p.n, [=] PD_HD(int64_t i) {
    position_update_with_init<kContact, kInit>(int32_t(i), p, b, mt, sp, c);
  });
}

template <class Exec>
void launch_position_update(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, StepParams sp,
                            ContactView c, bool with_init) {
  static_bools(
      [&](auto contact, auto init) {
        launch_position_update_variant<decltype(contact)::value, decltype(init)::value>(ex, p, b, mt, sp, c);
      },
      c.moved != nullptr, with_init);
}

template <class Exec>
void launch_velocity_update(Exec& ex, ParticlesView p, StepParams sp, bool with_gravity) {
  if (with_gravity)
    ex.parallel_for("pd/velocity_update[gravity]", p.n,
                    [=] PD_HD(int64_t i) { velocity_update_with_gravity<true>(int32_t(i), p, sp); });
  else
    ex.parallel_for("pd/velocity_update", p.n,
                    [=] PD_HD(int64_t i) { velocity_update_with_gravity<false>(int32_t(i), p, sp); });
}

// One step's velocity update and the next step's position update in one pass, where nothing on
// the host falls between the two steps. Six blocks of 256 resident (at most 40 registers, 45-48
// without): the pass 2-4% faster on the vase, the torus, the 1M plate and the explicit lattice;
// at eight (32 registers) the vase's and the torus's 5% slower (one H200, bench/NOTES.md).
template <bool kGravity, bool kContact, bool kInit, class Exec>
void launch_velocity_then_position_update_variant(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt,
                                                  StepParams sp, ContactView c) {
  static const std::string name = kernel_variant(
      "pd/velocity_position_update", {{"gravity", kGravity}, {"contact", kContact}, {"init", kInit}});
  ex.template parallel_for<6>(name.c_str(), p.n, [=] PD_HD(int64_t i) {
    velocity_then_position_update<kGravity, kContact, kInit>(int32_t(i), p, b, mt, sp, c);
  });
}

template <class Exec>
void launch_velocity_then_position_update(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt,
                                          StepParams sp, ContactView c, bool with_gravity, bool with_init) {
  static_bools(
      [&](auto gravity, auto contact, auto init) {
        launch_velocity_then_position_update_variant<decltype(gravity)::value, decltype(contact)::value,
                                                     decltype(init)::value>(ex, p, b, mt, sp, c);
      },
      with_gravity, c.moved != nullptr, with_init);
}

// Family build passes.
template <class Exec>
void launch_count_family(Exec& ex, ParticlesView p, HashView h, MaterialTable mt, int32_t* count) {
  ex.parallel_for("family/count", p.n, [=] PD_HD(int64_t i) { count_family(int32_t(i), p, h, mt, count); });
}

template <class Exec>
void launch_slice_length(Exec& ex, int32_t n, const int32_t* count, int64_t* length) {
  const int64_t slices = (int64_t(n) + kSliceWidth - 1) / kSliceWidth;
  ex.parallel_for("family/slices", slices,
                  [=] PD_HD(int64_t s) { slice_length(int32_t(s), n, count, length); });
}

template <class Exec>
void launch_fill_family(Exec& ex, ParticlesView p, HashView h, MaterialTable mt, BondsView b) {
  ex.parallel_for("family/fill", p.n, [=] PD_HD(int64_t i) {
    fill_family(int32_t(i), p, h, mt, b);
    sort_family(int32_t(i), p, b);
  });
}

// Bond-based set-up: the surface correction's factors, per particle then per bond.
template <class Exec>
void launch_surface_factor(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt, int round) {
  ex.parallel_for("family/surface_factor", p.n,
                  [=] PD_HD(int64_t i) { update_surface_factor(int32_t(i), p, b, mt, round); });
}

template <class Exec>
void launch_surface_bond_factors(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt,
                                 bool fold = false) {
  ex.parallel_for("family/surface_bond", p.n,
                  [=] PD_HD(int64_t i) { surface_bond_factors(int32_t(i), p, b, mt, fold); });
}

// State-based set-up: weighted volumes.
template <class Exec>
void launch_weighted_volume(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt) {
  ex.parallel_for("family/weighted_volume", p.n,
                  [=] PD_HD(int64_t i) { weighted_volume(int32_t(i), p, b, mt); });
}

template <class Exec>
void launch_stability_rate(Exec& ex, ParticlesView p, BondsView b, MaterialTable mt,
                           double collider_stiffness, double* rate) {
  ex.parallel_for("family/stability", p.n, [=] PD_HD(int64_t i) {
    rate[i] = stability_rate(int32_t(i), p, b, mt, collider_stiffness);
  });
}

// Bit k of words[w]: whether slot 32 w + k holds a broken bond (its neighbor is ~j < 0); changed[w]
// the bits that differ from words[w] as it was (Engine::bond_changes).
template <class Exec>
void launch_broken_bits(Exec& ex, ArrayView<const int32_t> neighbor, ArrayView<uint32_t> words,
                        ArrayView<uint32_t> changed) {
  ex.parallel_for("stats/broken_bits", words.size, [=] PD_HD(int64_t w) {
    const int64_t first = 32 * w, end = first + 32 < neighbor.size ? first + 32 : neighbor.size;
    uint32_t bits = 0;
    for (int64_t slot = first; slot < end; ++slot) bits |= uint32_t(neighbor[slot] < 0) << (slot - first);
    changed[w] = bits ^ words[w];
    words[w] = bits;
  });
}

// Reductions read once per frame.
template <class Exec>
int64_t reduce_broken_bonds(Exec& ex, BondsView b, const int32_t* intact) {
  return ex.template reduce_sum<int64_t>("stats/broken", b.n,
                                         [=] PD_HD(int64_t i) { return int64_t(b.count[i] - intact[i]); });
}

template <class Exec>
Energy reduce_energy(Exec& ex, ParticlesView p, BondsView b, ContactView c, MaterialTable mt, StepParams sp,
                     bool contact) {
  return ex.template reduce_sum<Energy>("stats/energy", p.n, [=] PD_HD(int64_t i) {
    return particle_energy(int32_t(i), p, b, c, mt, sp, contact);
  });
}

template <class Exec>
int64_t reduce_non_finite(Exec& ex, ParticlesView p) {
  return ex.template reduce_sum<int64_t>("stats/finite", p.n, [=] PD_HD(int64_t i) {
    return int64_t(!(is_finite(xyz(p.disp[i])) && is_finite(p.vel[i]) && is_finite(p.force[i])));
  });
}

}  // namespace pd
