// Plain views (raw pointers + sizes) passed by value into kernel bodies, and the small
// parameter structs the kernels read. Owning buffers live in the engine (engine_impl.h).
#pragma once

#include "cuda/array_view.h"
#include "cuda/pd_common.h"
#include "cuda/state_fields.h"
#include "cuda/vec3.h"

namespace pd {

// Per-particle flag bits.
enum ParticleFlag : uint8_t {
  kAnchored = 1u << 0,  // prescribed motion (its anchor group's, see AnchorMotion) whatever the forces
};

// Particle state, structure of arrays: the fields of cuda/state_fields.h, each a view that
// carries its length (checked under PERIFRAC_BOUNDS_CHECKS). Current position = X + u; bond
// vectors are formed from displacements (xi + (u_j - u_i)) to keep float32 round-off out of
// small strains.
#define PD_VIEW_MEMBER(name, Type, ...) ArrayView<Type> name;
struct ParticlesView {
  int32_t n = 0;
  PD_PARTICLE_FIELDS(PD_VIEW_MEMBER)

  PD_HD Vec3 position(int32_t i) const { return xyz(rest[i]) + xyz(disp[i]); }
  PD_HD real volume(int32_t i) const { return rest[i].w; }
  PD_HD real strain_limit(int32_t i) const { return disp[i].w; }
};

// Bond families in sliced-ELL layout: particles are grouped in slices of kSliceWidth;
// bond k of particle i lives at slice_offset[i / W] + k * W + i % W, so the threads of a
// warp read consecutive words for the same k. A broken bond keeps its partner as ~j (< 0).
constexpr int kSliceWidth = 32;

// Lattice families (implicit neighbours, host/lattice_families.h). A body laid out as a full
// box grid (x fastest, then y, z) with one material and volume has one stencil: the bond
// offsets its families use, in ascending partner order. A particle of such a body finds
// bond q's partner at its own index + offset[q] and its reference bond vector in the table,
// so the force loops read no partner index and no partner reference position. Its stored
// family lists the same bonds in the same (stencil) order, so per-bond state and every other
// reader of `neighbor` see the same slots. On a partitioned rank (cuda/parallel/) the whole
// run's offsets are not the rank's: a body's stencil there is `listed` (partners read from the
// lists, the geometry from the stencil), and a copy with the rank's local offsets serves the
// particles whose partners all sit at them (lattice_families.h rank_lattice_families).
struct StencilEntry {
  Vec4 xi;         // xyz: reference bond vector [m]; w: |xi|
  real inv_r0;     // 1 / |xi|
  real weight;     // beta V_j: the partner's volume inside the horizon (volume_fraction)
  int32_t offset;  // partner index minus own index
  int32_t pad;
};

struct Stencil {
  int32_t first = 0;   // first entry in LatticeView::entries
  int32_t size = 0;    // entries (<= 32 kLatticeWords)
  int32_t listed = 0;  // partners read from the family's list, not at the offsets (below)
};

constexpr int kLatticeWords = 16;  // stencils of up to 512 bonds (delta + lambda/2 <= 4.5 lambda)

struct LatticeView {
  int32_t words = 0;                 // mask words per particle (the largest stencil's)
  ArrayView<const int16_t> stencil;  // per particle: its stencil, or -1 (explicit family)
  ArrayView<const Stencil> stencils;
  ArrayView<const StencilEntry> entries;
  // Per particle, bit q of word w (stored at w * n + i) for stencil entry 32 w + q: the bond is
  // in the family (present; cuts remove bonds) and not broken (intact).
  ArrayView<const uint32_t> present;
  ArrayView<uint32_t> intact;
  // Scenes with weakened bonds only: the bonds whose strength factor is below 1, so that only
  // those read it (same layout).
  ArrayView<const uint32_t> weak;
  // Materials with the surface correction (cuda/kernels/surface_correction.h): per
  // particle the start of its row in `surface_table`, the stored bond factor of each stencil
  // entry. Particles placed alike in their body share a row, so a lattice bond's factor comes
  // from a small table that stays in cache instead of its slot, whose index the loop would
  // otherwise compute for every bond (lattice_families.h surface_rows).
  ArrayView<const int32_t> surface_row;
  ArrayView<const uint16_t> surface_table;
};

struct BondsView {
  int32_t n = 0;  // particles
  PD_BOND_FIELDS(PD_VIEW_MEMBER)
  // Scenes with box-grid bodies (null `lattice.stencil` otherwise).
  LatticeView lattice;

  PD_HD int64_t slot(int32_t i, int32_t k) const {
    return slice_offset[i / kSliceWidth] + int64_t(k) * kSliceWidth + (i % kSliceWidth);
  }
};
#undef PD_VIEW_MEMBER

// The order families and contact lists keep partners in: the particle's index in the whole run
// (its own index, unless the run is partitioned), so sums over them do not depend on the ranks.
PD_HD inline int32_t order_of(const ParticlesView& p, int32_t j) {
  return p.global_id ? p.global_id[j] : j;
}

PD_HD inline bool bond_intact(int32_t nb) {
  return nb >= 0;
}
PD_HD inline int32_t bond_partner(int32_t nb) {
  return nb >= 0 ? nb : ~nb;
}

// Spatial hash of cells of side `cell` (Teschner et al. 2003). Particles are sorted by
// bin; bin b holds sorted entries [bin_start[b], bin_end[b]). Several cells can share a
// bin, so users compare each candidate's own cell with the cell they are visiting.
struct HashView {
  uint32_t bins = 0;  // power of two
  real inv_cell = 0;
  ArrayView<uint32_t> key;       // bin of each particle, then sorted
  ArrayView<int32_t> sorted;     // particle ids in bin order
  ArrayView<int32_t> bin_start;  // first sorted entry of each bin, -1 when empty
  ArrayView<int32_t> bin_end;    // one past the last sorted entry
  // Contact lists only: per sorted entry, the particle's position and a quarter of its contact
  // spacing, so the partners of a cell are read in one contiguous run (launch_collection).
  ArrayView<Vec4> record;
};

// Contact pairs kept as Verlet lists (Verlet 1967): per particle, the particles that were
// closer than the pair's contact distance plus both particles' skins when the lists were built,
// in ascending index order. A particle's skin is `base` at rest and grows with its speed (up to
// `cap`), so that a fragment in flight does not force a build every few steps. The lists hold
// every pair in contact for as long as no particle has moved more than 0.9 of its skin since its
// list was built (`origin`); `position_update` raises `moved` when one has, and the engine
// rebuilds the lists before the next `collisions` (those of the particles that moved alone where
// they are few, contact_relist.h). Each particle has room for `capacity` partners, stored like the
// bonds' slices so that a warp reads partner k of its particles together: partner k of
// particle i at partner[k * n + i].
struct ContactView {
  int32_t n = 0;
  int32_t capacity = 0;
  real base = 0;                 // skin of a particle at rest [m]
  real per_speed = 0;            // skin per unit speed [s]
  real cap = 0;                  // largest skin [m]
  ArrayView<int32_t> count;      // partners of each particle (above capacity: the list overflowed)
  ArrayView<int32_t> partner;    // capacity x n partner indices
  ArrayView<Vec4> origin;        // xyz: each particle's displacement at its list's build, less the
                                 // frame's shift then (contact_frame.h); w: its skin
  Vec3 shift{0, 0, 0};           // the lists' frame's displacement since their full build
  Vec3 frame_velocity{0, 0, 0};  // and its velocity now
  int32_t* moved = nullptr;      // set to 1 by any particle that moved farther than 0.9 of its skin
  // The particles that raised `moved` since the last refresh (the first movers.size of them) and
  // how many did: the lists rebuilt for them alone where they are few (contact_relist.h).
  ArrayView<int32_t> movers;
  int32_t* mover_count = nullptr;
  int32_t* crowded = nullptr;  // set to 1 when more particles moved than `movers` holds
  PD_HD int64_t slot(int32_t i, int32_t k) const { return int64_t(k) * n + i; }
};

// Adds 1 to a counter many threads may increment at once; returns its value before.
PD_HD inline int32_t atomic_increment(int32_t* counter) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(counter, 1);
#else
  return __atomic_fetch_add(counter, 1, __ATOMIC_RELAXED);
#endif
}

// Stores v where many threads may store at once; returns the value it replaced.
PD_HD inline int32_t atomic_exchange(int32_t* slot, int32_t v) {
#if defined(__CUDA_ARCH__)
  return atomicExch(slot, v);
#else
  return __atomic_exchange_n(slot, v, __ATOMIC_RELAXED);
#endif
}

// Sets a flag (Exec::flag) that many threads may set at once, all to 1. On the GPU the flag lives
// in host memory: one store per warp (the lowest lane taking this path) rather than per thread.
PD_HD inline void raise_flag(int32_t* flag) {
#if defined(__CUDA_ARCH__)
  if ((threadIdx.x & 31u) == unsigned(__ffs(__activemask()) - 1))
    *reinterpret_cast<volatile int32_t*>(flag) = 1;
#else
  __atomic_store_n(flag, 1, __ATOMIC_RELAXED);
#endif
}

struct Cell {
  int32_t x, y, z;
};

// Cell index along one axis, clamped to +-2^30 so that a runaway or non-finite position (a
// blow-up the watchdog is about to report) still gives a valid cell and neighbour arithmetic
// (c +- 1) cannot overflow; NaN maps to the lower bound. On the GPU fmax/fmin do that in one
// instruction each; on the CPU they are library calls (17% of a million-particle set-up, spent in
// the family search), so the comparisons are written out, with the same result for every input.
PD_HD inline int32_t cell_coord(real v, real inv_cell) {
  constexpr real kLimit = real(1 << 30);
  const real f = std::floor(v * inv_cell);
#if defined(__CUDA_ARCH__)
  return int32_t(fmin(fmax(f, -kLimit), kLimit));
#else
  const real above = f >= -kLimit ? f : -kLimit;  // false for NaN, as fmax(NaN, -kLimit) = -kLimit
  return int32_t(above <= kLimit ? above : kLimit);
#endif
}
PD_HD inline Cell cell_of(Vec3 p, real inv_cell) {
  return {cell_coord(p.x, inv_cell), cell_coord(p.y, inv_cell), cell_coord(p.z, inv_cell)};
}
PD_HD inline bool same_cell(Cell a, Cell b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
// The bin of a cell. Blocks of 4 x 4 x 4 cells keep 64 consecutive bins: the block is hashed
// (Teschner et al. 2003) and the cell's place in its block, in Morton order, gives the low 6
// bits. Entries sorted by bin are then in space-filling order within each block, so a warp of
// consecutive entries (collisions run one thread per entry) works on one neighbourhood and
// reads the same cells; a plain hash of the cell scatters neighbours across the bins.
constexpr int kHashBlockBits = 2;  // log2 of the block side

PD_HD inline uint32_t cell_bin(Cell c, uint32_t bins) {
  const uint32_t h = (uint32_t(c.x >> kHashBlockBits) * 73856093u) ^
                     (uint32_t(c.y >> kHashBlockBits) * 19349663u) ^
                     (uint32_t(c.z >> kHashBlockBits) * 83492791u);
  uint32_t local = 0;
  for (int b = 0; b < kHashBlockBits; ++b)
    local |= ((uint32_t(c.x) >> b & 1u) << (3 * b)) | ((uint32_t(c.y) >> b & 1u) << (3 * b + 1)) |
             ((uint32_t(c.z) >> b & 1u) << (3 * b + 2));
  return ((h << (3 * kHashBlockBits)) | local) & (bins - 1u);
}

enum MaterialModel : uint8_t {
  kBondBased = 0,   // prototype microelastic brittle (PMB) springs, Poisson ratio 1/4
  kStateBased = 1,  // ordinary state-based linear peridynamic solid (Chen et al. sec. 4)
};

// Material constants seen by the kernels, derived on the host (host/material.cpp).
struct Material {
  uint8_t model = kBondBased;
  real horizon = 0;            // delta [m]
  real spacing = 0;            // lambda [m]
  real contact_spacing = 0;    // contact distance of two particles: (s_i + s_j) / 4 [m]
  real compression_alpha = 0;  // alpha of Levine eq. 5
  // Partial volumes: a neighbour whose cube overlaps the horizon sphere counts with the
  // overlapped fraction, so families reach delta + lambda/2; otherwise families end at delta.
  uint8_t partial_volumes = 1;
  PD_HD real family_radius() const { return partial_volumes ? horizon + real(0.5) * spacing : horizon; }
  // Surface correction (either model; cuda/kernels/surface_correction.h): a factor per bond that
  // restores the interior's response where a surface cuts families short. axial_sum: the
  // interior lattice family's per-axis sum the factors restore: bond-based sum_j n_x^4 |xi| beta
  // V_j, state-based sum_j n_x^2 |xi| beta V_j (the second moment's, omega |xi|^2 = delta |xi|).
  uint8_t surface_correction = 0;
  real axial_sum = 0;
  // The ghost surface correction instead (cuda/kernels/surface_ghosts.h): surface particles
  // complete their families with ghosts on their fitted quadratic field.
  uint8_t ghost_correction = 0;
  // Bond-based:
  real micromodulus = 0;  // c = 18 K / sum_j |xi| beta V_j over an interior lattice family [N/m^6]
  // State-based:
  real bulk_modulus = 0;      // K [Pa]
  real shear_modulus = 0;     // mu [Pa]
  real damage_alpha = 0;      // alpha of Chen eq. 18
  uint8_t chen_fracture = 1;  // 1: Chen eq. 18 from both ends; 0: stretch > max(tau_i, tau_j)
  uint8_t plastic = 0;
  real yield_psi0 = 0;     // Mitchell's yield constant psi_0 (Chen eq. 12)
  real plastic_limit = 0;  // Chen's gamma as a stretch: |e^p| <= plastic_limit |xi| (eq. 15)
  uint8_t anisotropic = 0;
  real aniso[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // G of Chen eq. 16, row major
};

constexpr int kMaxMaterials = 16;
struct MaterialTable {
  int32_t count = 0;
  Material m[kMaxMaterials];
};

// A spherical projectile moving at constant velocity (Levine eq. 7).
struct Projectile {
  Vec3 center0{0, 0, 0};  // centre at t = 0
  Vec3 velocity{0, 0, 0};
  real radius = 0;
  real strength = 0;  // K_S [Pa]
};

constexpr int kMaxProjectiles = 4;

// The motion of one anchor group at the time the step being computed ends (host/motion.h fills
// it each step). Unscripted groups keep each particle's own velocity (u += dt v, the velocity
// it started with); scripted ones follow a rigid motion about a pivot P given in rest space:
//   u = offset + (R - I)(X - P),  v = velocity + omega x R (X - P),
// with R - I given directly so that a small rotation loses no digits. A released group's
// particles move freely from then on.
struct AnchorMotion {
  uint8_t scripted = 0;
  uint8_t released = 0;
  Vec3 pivot{0, 0, 0};
  Vec3 offset{0, 0, 0};
  Vec3 velocity{0, 0, 0};
  Vec3 omega{0, 0, 0};
  real rotation_minus_identity[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // R - I, row major
};

constexpr int kMaxAnchors = 16;

// A rigid collider ([[colliders]] in a scene): an analytic shape placed by a rigid transform,
// which pushes the particles it touches by penalty contact with Coulomb friction and damping of
// the normal push (cuda/kernels/colliders.h). Its pose and velocity are those at the end of the
// step being computed (the motion script sets them, cuda/engine/motion.h).
enum ColliderShape : uint8_t {
  kColliderPlane = 0,     // the half-space below the plane through `center` normal to the shape's y
  kColliderSphere = 1,    // size.x: radius
  kColliderBox = 2,       // size: half extents along the shape's axes
  kColliderCapsule = 3,   // size.x: radius, size.y: half length of the segment along the shape's y
  kColliderCylinder = 4,  // size.x: radius, size.y: half length along the shape's y (flat ends)
  kColliderMesh = 5,      // a triangle mesh's distance grid (grid_*); size: half its bounding box
};

constexpr int kMaxColliders = 256;

// How a collider pushes: the penalty law with damping and friction (colliders.h), or LAMMPS's
// `fix indent` law, F = K (R - r)^2 on a point within the shape, neither damped nor rubbing.
enum ColliderLaw : uint8_t { kLawPenalty = 0, kLawLammpsIndent = 1 };

struct Collider {
  Vec3 center{0, 0, 0};
  real rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // shape frame to world, row major
  Vec3 velocity{0, 0, 0};                          // of the centre
  Vec3 omega{0, 0, 0};                             // angular velocity
  Vec3 size{0, 0, 0};
  real stiffness = 0;  // K [Pa]: a particle of volume V pressed in by d is pushed with K V^(1/3) d
  real friction_static = 0, friction_dynamic = 0;  // Coulomb coefficients
  real damping = 0;                                // of the normal push, as a ratio of critical
  real bound = 0;  // the shape's bounding radius about the centre (0: unbounded, a plane)
  uint8_t shape = kColliderPlane;
  uint8_t law = kLawPenalty;  // kLawLammpsIndent: `stiffness` is LAMMPS's K [N/m^5], on K d^2 V
  // kColliderMesh: the distance at nodes grid_origin + grid_cell (i, j, k) of the shape's frame,
  // i < grid_dims[0] fastest, from grid_offset in StepParams::collider_grids.
  Vec3 grid_origin{0, 0, 0};
  real grid_cell = 0;
  int32_t grid_dims[3] = {0, 0, 0};
  int64_t grid_offset = 0;
};

// The colliders binned on a coarse grid of dims^3 cubic cells from `lo` (cuda/engine/collider_grid.h):
// a particle reads the colliders whose reach overlaps its cell, and the unbounded ones (planes).
// lists: per cell the start of its colliders (cells + 1 entries), then the colliders of every cell,
// then the unbounded ones from `unbounded`. Empty: no colliders.
struct ColliderGridView {
  Vec3 lo{0, 0, 0};
  real inv_cell = 0;
  int32_t dims = 0;
  int32_t unbounded = 0;  // in `lists`, to its end
  ArrayView<const int32_t> lists;
};

// Everything the per-step kernels read that is not per-particle.
struct StepParams {
  real dt = 0;
  real time = 0;  // time at the end of the step being computed
  Vec3 gravity{0, 0, 0};
  uint8_t floor_enabled = 0;
  real floor_height = 0;  // floor is the plane y = floor_height (y is up)
  // No particle's reference y is below it (-infinity where the engine does not know): a
  // particle whose displacement keeps it above the floor from there is not read further
  // (below_floor, integrate.h).
  real lowest_rest_y = -INFINITY;
  real restitution = 1;
  real contact_stiffness = 0;  // K_c [Pa]
  int32_t n_projectiles = 0;
  Projectile projectile[kMaxProjectiles];
  AnchorMotion anchor[kMaxAnchors];       // indexed by ParticlesView::anchor
  ArrayView<const Collider> colliders;    // on the backend (the engine's copy); empty: none
  ArrayView<const float> collider_grids;  // the mesh colliders' distance grids, one after another
  // Per collider: its centre and bounding radius (w < 0: unbounded), which a particle's loop reads
  // before the whole collider, so a far collider costs one distance (16 bytes, not the struct).
  ArrayView<const Vec4> collider_spheres;
  ColliderGridView collider_grid;
};

// An anchored particle whose group has not been released: its motion is prescribed.
PD_HD inline bool held(int32_t i, const ParticlesView& p, const StepParams& sp) {
  return (p.flags[i] & kAnchored) && !sp.anchor[p.anchor[i]].released;
}

}  // namespace pd
