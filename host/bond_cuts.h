// Pre-cracks and weakened bonds (artist controls; Chen Fig. 17's pre-cracked sheet, Levine's
// selectively weakened glass): bonds whose rest segment crosses a cut triangle are removed from
// the families before the run (strength 0), or keep a strength factor in (0, 1) that scales
// their strain limit. Applied once by the engine right after the families are built.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cut_triangle.h"
#include "engine.h"

namespace pd {

// Strength of a weakened bond as stored per slot: q / 255.
constexpr int kStrengthLevels = 255;

// Removes (and compacts away) the bonds of `bonds` that cross a strength-0 triangle, and writes
// per slot the smallest strength of the triangles each remaining bond crosses, quantised to
// 1..255 (255 for bonds that cross none). `strength` is left empty when no bond is weakened.
// A bond crosses a triangle when its open rest segment meets the closed triangle; the test runs
// on the segment from the lower particle index to the higher, so both stored directions of a
// bond get the same answer. `rest` and `body` are the particles' rest positions and bodies.
BondCutCounts cut_bonds(const std::vector<CutTriangle>& cuts, const std::vector<Vec3>& rest,
                        const std::vector<int32_t>& body, BondLists& bonds, std::vector<uint8_t>& strength);

// True when the open segment p -> q meets the closed triangle (Moller-Trumbore, double).
bool segment_crosses_triangle(const std::array<double, 3>& p, const std::array<double, 3>& q,
                              const CutTriangle& t);

}  // namespace pd
