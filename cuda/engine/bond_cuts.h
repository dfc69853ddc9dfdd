// Pre-cracks and weakened bonds (artist controls; Chen Fig. 17's pre-cracked sheet, Levine's
// selectively weakened glass): bonds whose rest segment crosses a cut triangle are removed from
// the families before the run (strength 0), or keep a strength factor in (0, 1) that scales
// their strain limit. Applied once by the engine right after the families are built.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "cuda/engine/cut_triangle.h"
#include "cuda/engine/engine.h"

namespace pd {

// Strength of a weakened bond as stored per slot: q / 255.
constexpr int kStrengthLevels = 255;

// Removes (and compacts away) the bonds of `bonds` that cross a strength-0 triangle, and writes
// per slot the smallest strength of the triangles each remaining bond crosses, quantised to
// 1..255 (255 for bonds that cross none). `strength` is left empty when no bond is weakened.
// Shards (`shard`, `shard_strength`: ParticleSet's, or empty): a bond between particles of two
// different cells, or between a particle in a cell and one in none (-1, strength 255: a zone's
// edge), is weakened to the smaller of its ends' shard strengths too; so is a bond listed in
// `faces` (bond_key pairs in ascending order; only with shards).
// A bond crosses a triangle when its open rest segment meets the closed triangle; the test runs
// on the segment from the lower particle index to the higher, so both stored directions of a
// bond get the same answer. `rest` and `body` are the particles' rest positions and bodies; no
// bond is longer than `longest` (longest_bond_bound).
BondCutCounts cut_bonds(const std::vector<CutTriangle>& cuts, const std::vector<Vec3>& rest,
                        const std::vector<int32_t>& body, double longest, BondLists& bonds,
                        std::vector<uint8_t>& strength, const std::vector<int32_t>& shard = {},
                        const std::vector<uint8_t>& shard_strength = {},
                        const std::vector<uint64_t>& faces = {});

// One key per bond, the same from both ends: the lower particle index in the high 32 bits.
inline uint64_t bond_key(int32_t i, int32_t j) {
  return i < j ? uint64_t(uint32_t(i)) << 32 | uint32_t(j) : uint64_t(uint32_t(j)) << 32 | uint32_t(i);
}

// True when the open segment p -> q meets the closed triangle (Moller-Trumbore, double).
bool segment_crosses_triangle(const std::array<double, 3>& p, const std::array<double, 3>& q,
                              const CutTriangle& t);

// The crossing test for many bonds of length at most `reach`: the triangles binned on a grid of
// cells of side `reach`, so a bond is tested only against those near its first end.
class CutTester {
 public:
  // `reach`: the longest bond; `points`: where the bonds start (the triangles are listed only
  // where bonds from them can cross).
  CutTester(const std::vector<CutTriangle>& cuts, double reach, const std::vector<Vec3>& points);
  // The smallest strength among the triangles the bond between particle a at `pa` and particle b
  // at `pb` of body `body` crosses; 1 when it crosses none. The segment runs from the lower index.
  double strength(int32_t a, Vec3 pa, int32_t b, Vec3 pb, int32_t body) const;
  // True when no triangle lies near `p`: no bond from there is cut.
  bool clear(Vec3 p) const { return near(p) == nullptr; }

 private:
  const std::vector<int32_t>* near(Vec3 p) const;
  int64_t coord(double v) const;
  static int64_t key(int64_t x, int64_t y, int64_t z);

  const std::vector<CutTriangle>* cuts_;
  double inv_;
  std::unordered_map<int64_t, std::vector<int32_t>> bins_;
};

}  // namespace pd
