// The bond families, built once at set-up: partners within the horizon found through the
// spatial hash over reference positions, stored in sliced-ELL layout (BondsView); then the
// scene's pre-cracks and weakened surfaces applied; then, for box-grid bodies, the lattice
// families that find partners by offset (cuda/engine/lattice_families.h).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "cuda/engine/bond_cuts.h"
#include "cuda/engine/engine_state.h"
#include "cuda/engine/lattice_families.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/engine/spatial_hash.h"
#include "cuda/features.h"
#include "cuda/launch.h"

namespace pd {

// Lattice families on the backend: the host tables (kept to check and refresh the intact bits of
// a restored snapshot) and their device copies.
template <class Exec>
struct LatticeState {
  LatticeFamilies tables;
  DeviceArray<int16_t, Exec> stencil;
  DeviceArray<Stencil, Exec> stencils;
  DeviceArray<StencilEntry, Exec> entries;
  DeviceArray<uint32_t, Exec> present, intact, weak;
  DeviceArray<int32_t, Exec> surface_row;  // the surface correction (upload_surface_rows)
  DeviceArray<uint16_t, Exec> surface_table;
  // The particles whose stencil is `listed` (a partitioned rank's), ascending; the kernels run
  // them in a launch of their own (launch_springforces).
  std::vector<int32_t> listed_host;
  DeviceArray<int32_t, Exec> listed_ids;

  bool empty() const { return tables.stencils.empty(); }
  LatticeView view() const {
    LatticeView v;
    v.words = tables.words;
    v.stencil = view_of(stencil);
    v.stencils = view_of(stencils);
    v.entries = view_of(entries);
    v.present = view_of(present);
    v.intact = view_of(intact);
    v.weak = view_of(weak);
    v.surface_row = view_of(surface_row);
    v.surface_table = view_of(surface_table);
    return v;
  }
};

// Families as stored, copied back into `out`, whose vectors keep their memory when their size
// holds: a run reads its bonds every frame, and fresh memory for them each time cost more than
// the copy (the pages touched anew; bench/NOTES.md).
template <class Exec>
void download_bonds(const EngineState<Exec>& s, BondLists& out) {
  s.slice_offset.download(out.slice_offset);
  s.count.download(out.count);
  s.neighbor.download(out.neighbor);
}

template <class Exec>
BondLists download_bonds(const EngineState<Exec>& s) {
  BondLists out;
  download_bonds(s, out);
  return out;
}

// Counts, smallest, largest and mean family of the first `owned` families as stored.
inline void count_family_stats(FamilyStats& family, const std::vector<int32_t>& counts, int32_t owned) {
  const auto end = counts.begin() + owned;
  family.min = owned > 0 ? *std::min_element(counts.begin(), end) : 0;
  family.max = owned > 0 ? *std::max_element(counts.begin(), end) : 0;
  family.bonds = 0;
  for (auto c = counts.begin(); c != end; ++c) family.bonds += *c;
  family.mean = owned > 0 ? double(family.bonds) / double(owned) : 0;
}

// The bond arrays are the bulk of the memory: refused with a clear message, before they are
// allocated, when the backend has not enough free.
template <class Exec>
void check_bond_memory(int64_t slots, int32_t n, const KernelFeatures& features, Backend backend) {
  const double per_slot = field_bytes<kSlots>(
      FieldNeeds{features.state_based, features.plastic, false, false, features.surface_factors});
  const double need = double(slots) * per_slot;
  const double free = double(backend_available_bytes(backend));
  if (need <= free) return;
  throw ResourceError("the families hold " + std::to_string(slots) + " bond slots (" + std::to_string(n) +
                      " particles), which need " + format_bytes(need) + " of " +
                      (Exec::kDevice ? "GPU" : "host") + " memory; " + format_bytes(free) +
                      " are free. Lower --scale, the horizon or the particle count" +
                      (Exec::kDevice ? ", or run on a GPU with more memory" : ""));
}

// Partners within each particle's horizon (plus the partial-volume reach), in the order the
// kernels visit them; `count` and `intact` start as the family sizes. Families are built for the
// first `owned` particles (a partitioned rank's own; the ghosts after them have none) from every
// particle the state holds.
template <class Exec>
void build_families(DeviceMemory<Exec>& mem, EngineState<Exec>& s, int32_t owned,
                    const MaterialTable& materials, const KernelFeatures& features, Backend backend,
                    FamilyStats& family) {
  Exec& exec = mem.exec();
  // Cells no narrower than the longest reach a bond may have (family_reach).
  double radius = 0;
  for (int m = 0; m < materials.count; ++m) radius = std::max(radius, double(materials.m[m].family_radius()));
  std::vector<Vec4> rest;
  s.rest.download(rest);
  double extent = 0;
  for (const Vec4& x : rest) extent = std::max(extent, largest_coordinate(xyz(x)));
  SpatialHash<Exec> hash;
  hash.allocate(mem, s.n,
                real((radius * (1.0 + 2 * kHorizonSlack) + 2 * kPositionSlack * extent) * (1.0 + 1e-6)));
  ParticlesView p = s.particles();
  launch_reset_bins(exec, "family/reset", hash.view(true));
  launch_collection<false>(exec, "family/collection", p, hash.view(false), hash.view(true));
  p.n = owned;

  launch_count_family(exec, p, hash.view(true), materials, s.count.data());
  const int64_t slices = (int64_t(s.n) + kSliceWidth - 1) / kSliceWidth;
  auto length = mem.template make<int64_t>(size_t(slices));
  s.slice_offset = mem.template make<int64_t>(size_t(slices + 1));
  launch_slice_length(exec, s.n, s.count.data(), length.data());
  const int64_t slots = exec.exclusive_scan(length.data(), s.slice_offset.data(), slices);
  exec.upload(s.slice_offset.data() + slices, &slots, sizeof(int64_t));
  mem.drop(length);

  check_bond_memory<Exec>(slots, s.n, features, backend);
  s.neighbor = mem.template make_zeroed<int32_t>(size_t(std::max<int64_t>(slots, 1)));
  launch_fill_family(exec, p, hash.view(true), materials, s.bonds());
  hash.release(mem);

  std::vector<int32_t> counts;
  s.count.download(counts);
  family.slots = slots;
  count_family_stats(family, counts, owned);
  s.intact.upload(counts);
}

// Pre-cracks and weakened surfaces: bonds crossing them leave the families (compacted on the
// host) or keep a strength factor, before anything is derived from the families. Returns
// whether some bond was weakened (the `strength` field then exists). `lists` is left holding the
// families as uploaded.
template <class Exec>
bool apply_cuts(DeviceMemory<Exec>& mem, EngineState<Exec>& s, int32_t owned, const SimulationInput& in,
                FamilyStats& family, BondLists& lists) {
  download_bonds(s, lists);
  std::vector<uint8_t> strength;
  family.cuts =
      cut_bonds(in.cuts, in.particles.rest, in.particles.body, longest_bond_bound(in.particles, in.materials),
                lists, strength, in.particles.shard, in.particles.shard_strength, in.face_bonds);
  s.neighbor.upload(lists.neighbor);
  s.count.upload(lists.count);
  s.intact.upload(lists.count);
  count_family_stats(family, lists.count, owned);
  if (strength.empty()) return false;
  s.strength = mem.make_from(strength);
  return true;
}

// Box-grid bodies find their partners by offset (cuda/engine/lattice_families.h), from the
// families `lists` (as on the backend). Returns whether some body has a stencil.
template <class Exec>
bool build_lattice_families(DeviceMemory<Exec>& mem, const EngineState<Exec>& s, const ParticleSet& ps,
                            const MaterialTable& materials, bool weak_bonds, LatticeState<Exec>& lattice,
                            FamilyStats& family, const BondLists& lists) {
  return upload_lattice_families(mem, s, lattice_families(ps, materials, lists), weak_bonds, lattice, family,
                                 lists);
}

// Lattice tables made elsewhere (a partitioned rank's part of the whole run's, whose partners are
// read from the lists) on the backend; `lists` the families as on the backend. Returns whether
// some particle has a stencil.
template <class Exec>
bool upload_lattice_families(DeviceMemory<Exec>& mem, const EngineState<Exec>& s, LatticeFamilies tables,
                             bool weak_bonds, LatticeState<Exec>& lattice, FamilyStats& family,
                             const BondLists& lists) {
  lattice.tables = std::move(tables);
  family.lattice_particles = lattice.tables.particles();
  family.lattice_listed = lattice.tables.listed_particles();
  if (lattice.empty()) return false;
  lattice.stencil = mem.make_from(lattice.tables.stencil);
  lattice.stencils = mem.make_from(lattice.tables.stencils);
  lattice.entries = mem.make_from(lattice.tables.entries);
  lattice.present = mem.make_from(lattice.tables.present);
  lattice.intact = mem.make_from(lattice.tables.intact);
  lattice.listed_host.clear();
  for (size_t i = 0; i < lattice.tables.stencil.size(); ++i) {
    const int16_t st = lattice.tables.stencil[i];
    if (st >= 0 && lattice.tables.stencils[size_t(st)].listed) lattice.listed_host.push_back(int32_t(i));
  }
  lattice.listed_ids = mem.make_from(lattice.listed_host);
  if (!weak_bonds) return true;
  std::vector<uint8_t> strength;
  s.strength.download(strength);
  mark_weak_lattice_bonds(lattice.tables, lists, strength);
  lattice.weak = mem.make_from(lattice.tables.weak);
  return true;
}

// The surface correction's factors of the lattice particles' bonds (set at their slots) as rows
// of factors per stencil entry on the backend (lattice_families.h surface_rows), for the
// force and dilatation kernels of either model.
template <class Exec>
void upload_surface_rows(DeviceMemory<Exec>& mem, const EngineState<Exec>& s, LatticeState<Exec>& lattice,
                         FamilyStats& family, const BondLists& lists) {
  std::vector<uint16_t> factors;
  s.surface_bond.download(factors);
  const SurfaceRows rows = surface_rows(lattice.tables, lists, factors);
  lattice.surface_row = mem.make_from(rows.row);
  lattice.surface_table = mem.make_from(rows.table);
  family.surface_rows = rows.rows;
}

// After a restore: the intact bits follow the restored families (the layout as built, the
// partners as restored).
template <class Exec>
void refresh_lattice_after_restore(const EngineState<Exec>& s, const std::vector<int32_t>& neighbor,
                                   LatticeState<Exec>& lattice) {
  BondLists lists;
  s.slice_offset.download(lists.slice_offset);
  s.count.download(lists.count);
  lists.neighbor = neighbor;
  refresh_lattice_intact(lattice.tables, lists);
}

// Smallest stable step over the particles, from the families as built and the stiffest
// collider's push (Engine::critical_time_step).
template <class Exec>
double stable_time_step(DeviceMemory<Exec>& mem, const ParticlesView& p, const BondsView& b,
                        const MaterialTable& materials, double collider_stiffness,
                        const std::vector<double>& extra_rate = {}) {
  auto rate = mem.template make<double>(size_t(p.n));
  launch_stability_rate(mem.exec(), p, b, materials, collider_stiffness, rate.data());
  std::vector<double> host;
  rate.download(host);
  mem.drop(rate);
  for (size_t i = 0; i < extra_rate.size() && i < host.size(); ++i) host[i] += extra_rate[i];
  const double fastest = *std::max_element(host.begin(), host.end());
  return fastest > 0 ? std::sqrt(2.0 / fastest) : std::numeric_limits<double>::infinity();
}

}  // namespace pd
