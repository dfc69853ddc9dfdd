#include "cuda/engine/bond_cuts.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace pd {

namespace {

using P3 = std::array<double, 3>;

P3 sub(const P3& a, const P3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
P3 cross3(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const P3& a, const P3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
P3 to_p3(Vec3 v) {
  return {double(v.x), double(v.y), double(v.z)};
}

}  // namespace

CutTester::CutTester(const std::vector<CutTriangle>& cuts, double reach, const std::vector<Vec3>& points)
    : cuts_(&cuts), inv_(1 / reach) {
  // The cells a bond from one of `points` can start in: a triangle is listed in those of its box
  // only (a crack far larger than the bodies costs no more than one across them).
  P3 lo_bound{INFINITY, INFINITY, INFINITY}, hi_bound{-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& v : points) {
    const P3 p = to_p3(v);
    for (size_t a = 0; a < 3; ++a) {
      lo_bound[a] = std::min(lo_bound[a], p[a]);
      hi_bound[a] = std::max(hi_bound[a], p[a]);
    }
  }
  for (size_t t = 0; t < cuts.size(); ++t) {
    std::array<int64_t, 3> lo{}, hi{};
    bool inside = true;
    for (size_t a = 0; a < 3; ++a) {
      double mn = cuts[t].corner[0][a], mx = mn;
      for (const P3& c : cuts[t].corner) {
        mn = std::min(mn, c[a]);
        mx = std::max(mx, c[a]);
      }
      mn = std::max(mn - reach, lo_bound[a]);
      mx = std::min(mx + reach, hi_bound[a]);
      inside = inside && mn <= mx;
      if (!inside) break;
      lo[a] = coord(mn);
      hi[a] = coord(mx);
    }
    if (!inside) continue;
    for (int64_t z = lo[2]; z <= hi[2]; ++z)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t x = lo[0]; x <= hi[0]; ++x) bins_[key(x, y, z)].push_back(int32_t(t));
  }
}

int64_t CutTester::coord(double v) const {
  return int64_t(std::floor(v * inv_));
}

int64_t CutTester::key(int64_t x, int64_t y, int64_t z) {
  return (x & 0x1FFFFF) | ((y & 0x1FFFFF) << 21) | ((z & 0x1FFFFF) << 42);
}

const std::vector<int32_t>* CutTester::near(Vec3 p) const {
  const auto it = bins_.find(key(coord(p.x), coord(p.y), coord(p.z)));
  return it == bins_.end() ? nullptr : &it->second;
}

double CutTester::strength(int32_t a, Vec3 pa, int32_t b, Vec3 pb, int32_t body) const {
  const std::vector<int32_t>* candidates = near(pa);
  if (!candidates) return 1;
  const P3 lo = to_p3(a < b ? pa : pb), hi = to_p3(a < b ? pb : pa);
  double weakest = 1;
  for (int32_t t : *candidates) {
    const CutTriangle& tri = (*cuts_)[size_t(t)];
    if ((tri.body < 0 || tri.body == body) && tri.strength < weakest && segment_crosses_triangle(lo, hi, tri))
      weakest = tri.strength;
  }
  return weakest;
}

bool segment_crosses_triangle(const P3& p, const P3& q, const CutTriangle& t) {
  const P3 e1 = sub(t.corner[1], t.corner[0]), e2 = sub(t.corner[2], t.corner[0]), d = sub(q, p);
  const P3 h = cross3(d, e2);
  const double det = dot3(e1, h);
  if (det == 0) return false;  // the segment lies parallel to the triangle's plane
  const double f = 1 / det;
  const P3 s = sub(p, t.corner[0]);
  const double u = f * dot3(s, h);
  if (u < 0 || u > 1) return false;
  const P3 r = cross3(s, e1);
  const double v = f * dot3(d, r);
  if (v < 0 || u + v > 1) return false;
  const double along = f * dot3(e2, r);
  return along > 0 && along < 1;
}

BondCutCounts cut_bonds(const std::vector<CutTriangle>& cuts, const std::vector<Vec3>& rest,
                        const std::vector<int32_t>& body, double longest, BondLists& bonds,
                        std::vector<uint8_t>& strength, const std::vector<int32_t>& shard,
                        const std::vector<uint8_t>& shard_strength, const std::vector<uint64_t>& faces) {
  BondCutCounts report;
  strength.clear();
  const bool shards = !shard.empty();
  if ((cuts.empty() || !(longest > 0)) && !shards) return report;
  const BondsView b = bonds.view();
  const int32_t n = b.n;

  // The grid's cell: the longest bond, so every bond starts in a cell that lists what it crosses.
  const std::unique_ptr<CutTester> tester =
      cuts.empty() || !(longest > 0) ? nullptr : std::make_unique<CutTester>(cuts, longest, rest);

  // Per slot: the strength of the weakest triangle the bond crosses (1 for none) or, between two
  // shards, the shards' strength; then each family is compacted past its removed bonds, in order.
  std::vector<uint8_t> level(bonds.neighbor.size(), uint8_t(kStrengthLevels));
  int64_t removed = 0, weakened = 0;
#pragma omp parallel for reduction(+ : removed, weakened) schedule(dynamic, 256)
  for (int32_t i = 0; i < n; ++i) {
    const bool near_cut = tester && !tester->clear(rest[size_t(i)]);
    if (!near_cut && !shards) continue;
    int32_t kept = 0;
    for (int32_t k = 0; k < b.count[i]; ++k) {
      const int64_t slot = b.slot(i, k);
      const int32_t j = bond_partner(b.neighbor[slot]);
      double weakest =
          near_cut ? tester->strength(i, rest[size_t(i)], j, rest[size_t(j)], body[size_t(i)]) : 1;
      if (weakest <= 0) {
        ++removed;
        continue;
      }
      uint8_t q =
          weakest < 1
              ? uint8_t(std::clamp(std::lround(weakest * kStrengthLevels), 1L, long(kStrengthLevels) - 1))
              : uint8_t(kStrengthLevels);
      // A face between two cells, or between a cell and a particle in none (a zone's edge; a
      // particle in none has strength 255), or a listed one (a pattern's).
      if (shards && (shard[size_t(j)] != shard[size_t(i)] ||
                     (!faces.empty() && std::binary_search(faces.begin(), faces.end(), bond_key(i, j)))))
        q = std::min({q, shard_strength[size_t(i)], shard_strength[size_t(j)]});
      const int64_t to = b.slot(i, kept++);
      b.neighbor[to] = b.neighbor[slot];
      level[size_t(to)] = q;
      weakened += q < kStrengthLevels;
    }
    bonds.count[size_t(i)] = kept;
  }
  report.removed = removed;
  report.weakened = weakened;
  if (weakened > 0) strength = std::move(level);
  return report;
}

}  // namespace pd
