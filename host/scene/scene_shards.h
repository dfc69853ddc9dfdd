// Shards ([[shards]], issue 31): which Voronoi cell each particle of a body lies in, so that the
// engine weakens the bonds between cells (cuda/engine/bond_cuts.h) and the body breaks into
// pieces of cells, never of single particles.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cuda/engine/particle_set.h"
#include "host/scene/scene.h"

namespace pd {

// The cells' seeds of one body: a grid of spacing `size` over the body's rest bounding box, each
// seed moved from its grid cell's centre by jitter x size x U(-1/2, 1/2) per axis.
struct ShardSeeds {
  double size = 0;
  std::array<double, 3> origin{};
  std::array<int64_t, 3> n{};
  std::vector<std::array<double, 3>> seed;  // x fastest
  // The seed nearest to x (the lower index on a tie): searched over the grid cells within 2 of
  // x's, which hold it (a seed stays in its grid cell, and every point of a cell is within
  // sqrt(3) size of its seed, nearer than any seed 2 cells away).
  int64_t nearest(const std::array<double, 3>& x) const;
};

// What the [[shards]] patterns made (host/app/shards_pattern.h).
struct ShardsPatternReport {
  int64_t faces = 0;   // bonds weakened: the first run's broken bonds, less those inside a dust cell
  int64_t dust = 0;    // particles of the first run's pieces under kPatternPieceParticles
  int64_t cells = 0;   // the cells the dust was grouped into
  int64_t bodies = 0;  // bodies with a pattern
  // Dust that holds by its own dust_hold: (the body's material table entry, the dust's copy of it).
  std::vector<std::pair<uint16_t, uint16_t>> dust_materials;
};

// A piece of a pattern's run with fewer particles than this is dust, grouped into cells of `size`.
constexpr int64_t kPatternPieceParticles = 8;

ShardSeeds shard_seeds(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double size,
                       double jitter, uint64_t seed);

// A copy of material table entry `material` (its index), for `part` of a body whose shards hold
// apart from the rest of it (a zone, a pattern's dust): its compression strengthening is then
// raised on its own. Throws SceneError naming `key` when the table holds kMaxMaterials already.
uint16_t copy_material_entry(const Scene& scene, const std::string& key, const std::string& part,
                             MaterialTable& materials, uint16_t material);

// The byte k nearest 255 / hold (1..254): a face keeps k / 255 of limits raised by 255 / k.
uint8_t shard_strength_byte(double hold);

// The cells of table `table` (its size and jitter; seeds over the members' rest bounding box,
// drawn from simulation.seed, the table and `body`) of the particles `members` of that body:
// per member its cell, numbered from `next` on in the order first met (cells holding no member
// get no number; `next` advances). Throws SceneError naming shards[table].size when the box
// would need more than kMaxShardCells cells.
std::vector<int64_t> number_cells(const Scene& scene, size_t table, size_t body, const ParticleSet& ps,
                                  const std::vector<size_t>& members, int64_t& next);

struct ShardReport {
  int64_t cells = 0;      // cells holding at least one particle
  int64_t particles = 0;  // particles in cells
  // Zones that hold part of a body: (the body's material table entry, the zone's copy of it).
  std::vector<std::pair<uint16_t, uint16_t>> zone_materials;
};

// Fills ps.shard and ps.shard_strength for the bodies of scene.shards (body indices as in
// scene.bodies) and multiplies their particles' strain limits by `hold` (as 255 / k for the
// integer k nearest 255 / hold, so that k / 255 gives a bond between cells exactly the limit it
// had: hold 3 is 3, hold 10 is 9.81), and their material's compression strengthening (Levine
// eq. 5's alpha, one material table entry per body) by the same, so that a face's limit
// w max(tau'_i, tau'_j) is the material's under compression too; leaves both empty when
// the scene has none. With a zone (`radius`), only the body's particles within it get cells;
// they take a copy of the body's material entry (ShardReport::zone_materials), whose compression
// strengthening is raised, and the bonds across the zone's edge are faces (cut_bonds). Cells are
// numbered over all bodies. Tables with a `pattern` are left to apply_shards_pattern
// (host/app/shards_pattern.h); where no particle gets a cell both fields stay empty. Throws
// SceneError when a body would need more than kMaxShardCells cells, or a zone a material entry
// beyond kMaxMaterials.
constexpr int64_t kMaxShardCells = int64_t(1) << 26;
ShardReport assign_shards(const Scene& scene, ParticleSet& ps, MaterialTable& materials);

}  // namespace pd
