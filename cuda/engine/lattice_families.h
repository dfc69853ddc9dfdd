// Lattice families (implicit neighbours, cuda/views.h LatticeView): which bodies are full box
// grids, their stencils, and per particle which stencil bonds its family holds and which of
// them are intact. Derived from the families as built (after cuts), so a lattice particle's
// bonds are exactly its listed ones, in the same order.
#pragma once

#include <cstdint>
#include <vector>

#include "cuda/engine/engine.h"

namespace pd {

struct LatticeFamilies {
  int32_t words = 0;                  // mask words per particle
  std::vector<int16_t> stencil;       // per particle: its stencil, or -1
  std::vector<Stencil> stencils;      // one per box-grid body (a rank: and one with local offsets)
  std::vector<StencilEntry> entries;  // the stencils' entries, ascending offset within each
  std::vector<uint32_t> present;      // words x n, word w of particle i at w * n + i
  std::vector<uint32_t> intact;       // same layout
  std::vector<uint32_t> weak;         // same layout; scenes with weakened bonds only
  int64_t particles() const;          // particles with a lattice family
  int64_t listed_particles() const;   // of them, those whose stencil is `listed`
};

// The bodies of `ps` whose particles are contiguous, laid out as a box grid of at least 2 per
// axis (x fastest, then y, z; positions within 1e-3 spacing of the grid), of one material and
// one volume, whose families are ascending and use offsets that identify their bonds (grid
// wider than the stencil along x and y), get a stencil; the others keep explicit families.
LatticeFamilies lattice_families(const ParticleSet& ps, const MaterialTable& mt, const BondLists& bonds);

// The particles of `ps` in bodies laid out as box grids (as lattice_families finds them, before
// its checks of the families): a function of the particles only, the same on every rank.
int64_t box_grid_particles(const ParticleSet& ps);

// What a partitioned rank's lattice tables need of the other ranks (cuda/parallel/): whether
// every rank's families of a body fit a stencil, and the union of the index offsets they use.
struct StencilReduce {
  virtual ~StencilReduce() = default;
  virtual bool all(bool mine) = 0;
  virtual std::vector<int32_t> union_of(const std::vector<int32_t>& mine) = 0;  // sorted
};

// A partitioned rank's part of the tables lattice_families makes for the whole run `ps`, from
// the rank's own families (`local`, partners as local indices, `global` mapping them to the whole
// run's, its own particles first): rows in the rank's local order. Collective over the ranks.
// Each body's stencil is the whole run's, `listed`; where the rank's own particles of the body
// sit in its local order as on a grid of their own (a partition's box of the body in ascending
// global index), a copy of it with the local offsets serves every particle whose partners all
// sit at them, so those read no partner index, as on one rank.
LatticeFamilies rank_lattice_families(const ParticleSet& ps, const MaterialTable& mt, const BondLists& local,
                                      const std::vector<int32_t>& global, int32_t owned,
                                      StencilReduce& reduce);

// Sets the weak bits: the bonds whose per-slot strength (bond_cuts.h) is below 1.
void mark_weak_lattice_bonds(LatticeFamilies& lf, const BondLists& bonds,
                             const std::vector<uint8_t>& strength);

// The surface correction's stored bond factors of the lattice particles as rows of a table, one
// per stencil entry (0 where the family lacks the entry, never read): per particle the start of
// its row, or -1 (an explicit family), and the rows, each stored once however many particles
// have it. `surface_bond` holds the factors at the slots of `bonds`.
struct SurfaceRows {
  std::vector<int32_t> row;     // per particle
  std::vector<uint16_t> table;  // the rows, one after another
  int64_t rows = 0;
};
SurfaceRows surface_rows(const LatticeFamilies& lf, const BondLists& bonds,
                         const std::vector<uint16_t>& surface_bond);

// Recomputes the intact bits from `bonds` (a restored snapshot). Throws std::invalid_argument
// when a lattice particle's listed bonds are not its present stencil bonds in stencil order
// (partners checked by offset where its stencil is not `listed`).
void refresh_lattice_intact(LatticeFamilies& lf, const BondLists& bonds);

}  // namespace pd
