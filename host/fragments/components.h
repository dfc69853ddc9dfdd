// Connected components of the unbroken element adjacency: the fragments of a frame. A pair of
// adjacent particles stays connected while their bond is intact in both families (a bond broken
// in either direction separates them), or, for touching elements farther apart than the horizon,
// while a common neighbour is still bonded to both (face_links.h). Bonds never heal, so
// components only ever split.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/fragments/adjacency.h"
#include "host/fragments/face_links.h"

namespace pd {

// Particles grouped by component. A component's id is the smallest particle index in it, so ids
// are deterministic and a fragment keeps its id until it splits (then the part holding that
// particle keeps it). Components are numbered c = 0 .. count()-1 in increasing id.
struct Components {
  std::vector<int32_t> id;       // per particle: id of its component
  std::vector<int32_t> index;    // per particle: number c of its component
  std::vector<int32_t> start;    // count() + 1 entries
  std::vector<int32_t> members;  // component c: members[start[c] .. start[c + 1]), ascending

  size_t count() const { return start.empty() ? 0 : start.size() - 1; }
  int32_t size(size_t c) const { return start[c + 1] - start[c]; }
  int32_t component_id(size_t c) const { return members[size_t(start[c])]; }
};

// Groups particles by per-particle ids (any values in [0, n), e.g. a frame file's `component`
// array); components are numbered in order of first appearance. Throws std::invalid_argument
// for an id outside [0, n).
Components components_from_ids(std::vector<int32_t> id);

// Finds components every frame for one family layout.
class ComponentFinder {
 public:
  // Binds each adjacent pair to the bond slots that hold it (face_links.h). Throws
  // std::invalid_argument when the sizes differ or the adjacency is not symmetric.
  ComponentFinder(const ElementAdjacency& adjacency, const BondLists& bonds);

  // Components of `bonds` (the same families, as the engine holds them now) into `out`, whose
  // storage is reused from frame to frame like the finder's own scratch arrays.
  void find(const BondLists& bonds, Components& out);

  size_t pairs() const { return pairs_.size(); }
  const FaceLinks& links() const { return links_; }

 private:
  size_t n_ = 0;
  size_t slots_ = 0;
  std::vector<std::array<int32_t, 2>> pairs_;  // adjacent pairs, a < b
  FaceLinks links_;                            // what holds each pair
  std::vector<uint8_t> intact_;                // scratch: pair still bonded
  std::vector<int32_t> parent_;                // scratch: union-find forest
};

// Component count, sizes and masses for the frame log and fragments.csv: histogram[b] counts the
// components of 2^b .. 2^(b+1)-1 particles; singles are the components of one particle (dust).
// A single may still hold by a bond to a particle it shares no face with (a diagonal bond), and
// then moves with it; free particles have no intact bond at all and fly on their own.
struct ComponentStats {
  size_t count = 0;
  int32_t largest = 0;  // particles in the largest component
  std::vector<int64_t> histogram;
  int64_t singles = 0;
  double mass = 0, single_mass = 0, largest_mass = 0;  // [kg]: all, in singles, of the heaviest
  bool free_counted = false;                           // free_mass known (bonds given)
  double free_mass = 0;                                // [kg] in particles without an intact bond
};

// The statistics of `c`, with each particle's `mass` (empty: masses not counted, all 0) and, where
// `bonds` is given, the mass of the free particles.
ComponentStats component_stats(const Components& c, const std::vector<real>& mass = {},
                               const BondLists* bonds = nullptr);

// One log field, e.g. "fragments 37 (1:21 2-3:9 4-7:4 65536-131071:1)", with the mass in singles
// when masses were counted, e.g. "... singles 0.8% of the mass", and in free particles when they
// were counted, "... singles 0.8% of the mass (free 0.5%)".
std::string format_component_stats(const ComponentStats& s);

}  // namespace pd
