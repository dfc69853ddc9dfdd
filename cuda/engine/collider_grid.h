// The colliders binned on a coarse grid, so a particle's `bodyforces` reads only the colliders
// whose reach overlaps its cell (and the unbounded planes): the cost per particle stays about
// constant with 64 or more colliders. Built on the host at start and whenever the colliders move.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "cuda/views.h"

namespace pd {

class ColliderGrid {
 public:
  // Bins `colliders` for particles no larger than `largest` (V^(1/3)) into `lists` (the layout of
  // ColliderGridView) and returns the view's grid fields (its `lists` left for the caller to set).
  static ColliderGridView build(const std::vector<Collider>& colliders, real largest,
                                std::vector<int32_t>& lists) {
    ColliderGridView g;
    // Each bounded collider's reach: its bounding sphere grown by a particle's half size.
    std::vector<int32_t> bounded, unbounded;
    Vec3 lo{real(INFINITY), real(INFINITY), real(INFINITY)},
        hi{-real(INFINITY), -real(INFINITY), -real(INFINITY)};
    for (size_t k = 0; k < colliders.size(); ++k) {
      const Collider& c = colliders[k];
      if (!(c.bound > 0)) {
        unbounded.push_back(int32_t(k));
        continue;
      }
      bounded.push_back(int32_t(k));
      const real r = reach(c, largest);
      lo = {std::min(lo.x, c.center.x - r), std::min(lo.y, c.center.y - r), std::min(lo.z, c.center.z - r)};
      hi = {std::max(hi.x, c.center.x + r), std::max(hi.y, c.center.y + r), std::max(hi.z, c.center.z + r)};
    }
    lists.clear();
    if (bounded.empty()) {
      lists.push_back(0);  // one empty cell, never entered (dims 0)
      g.unbounded = 1;
    } else {
      g.dims = int32_t(std::clamp(std::ceil(std::cbrt(8.0 * double(bounded.size()))), 1.0, 32.0));
      const real side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / real(g.dims);
      g.lo = lo;
      g.inv_cell = side > 0 ? real(1) / side : real(0);
      const int32_t cells = g.dims * g.dims * g.dims;
      std::vector<std::vector<int32_t>> in_cell(static_cast<size_t>(cells));
      for (int32_t k : bounded) {  // every cell the collider's reach box overlaps
        const Collider& c = colliders[size_t(k)];
        const real r = reach(c, largest);
        int32_t first[3], last[3];
        const real centre[3] = {c.center.x, c.center.y, c.center.z}, origin[3] = {lo.x, lo.y, lo.z};
        for (int a = 0; a < 3; ++a) {
          first[a] = std::clamp(int32_t(std::floor((centre[a] - r - origin[a]) * g.inv_cell)), 0, g.dims - 1);
          last[a] = std::clamp(int32_t(std::floor((centre[a] + r - origin[a]) * g.inv_cell)), 0, g.dims - 1);
        }
        for (int32_t z = first[2]; z <= last[2]; ++z)
          for (int32_t y = first[1]; y <= last[1]; ++y)
            for (int32_t x = first[0]; x <= last[0]; ++x)
              in_cell[size_t((z * g.dims + y) * g.dims + x)].push_back(k);
      }
      lists.resize(size_t(cells) + 1);
      int32_t next = cells + 1;
      for (int32_t cell = 0; cell < cells; ++cell) {
        lists[size_t(cell)] = next;
        next += int32_t(in_cell[size_t(cell)].size());
      }
      lists[size_t(cells)] = next;
      for (const std::vector<int32_t>& items : in_cell) lists.insert(lists.end(), items.begin(), items.end());
      g.unbounded = int32_t(lists.size());
    }
    lists.insert(lists.end(), unbounded.begin(), unbounded.end());
    return g;
  }

 private:
  static real reach(const Collider& c, real largest) { return real(1.0001) * c.bound + real(0.5) * largest; }
};

}  // namespace pd
