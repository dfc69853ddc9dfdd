#include "cuda/parallel/partition.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

#include "cuda/engine/bond_cuts.h"

namespace pd {

namespace {

// Bonds a particle is expected to have: the particles of its volume that fit in its family's ball.
// A volume below an eighth of the cell lambda^3 counts as that eighth: a mesh's sliver tets (down to
// 1e-16 of the median volume) have the partners their neighbours' volumes leave room for, not
// 10^16 of them.
double expected_bonds(const ParticleSet& ps, const MaterialTable& mt, size_t i) {
  const Material& m = mt.m[ps.material[i]];
  const double r = double(m.family_radius()), lambda = double(m.spacing);
  const double volume = std::max({double(ps.volume[i]), 0.125 * lambda * lambda * lambda, 1e-300});
  return std::max(1.0, 4.18879020478639098 * r * r * r / volume);
}

struct Box {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  void add(const Vec3& p) {
    const double c[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  bool contains(const Vec3& p, double margin) const {
    const double c[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a)
      if (c[a] < lo[a] - margin || c[a] > hi[a] + margin) return false;
    return true;
  }
};

double coordinate(const Vec3& p, int axis) {
  return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
}

// A particle's weight in the bisection: its expected bonds in fixed point (2^-16), so that every
// sum is exact and the same in any order and on any number of threads: every rank computes the
// partition alone and all must agree. At most 2^14 bonds count (2^30 per particle), so the sums of
// up to 2^31 particles stay within 2^61.
using Weight = int64_t;
constexpr double kMostCountedBonds = 16384;
Weight bisection_weight(const ParticleSet& ps, const MaterialTable& mt, size_t i) {
  return std::llround(std::ldexp(std::min(expected_bonds(ps, mt, i), kMostCountedBonds), 16));
}

// The position, in the order of `keyed` sorted, of the first element at which the weight in
// front of it plus half its own reaches left / count of the total (keyed.size() if none): a
// weighted quickselect, O(n) expected, serial (it replaces a parallel sort of the whole part,
// O(n log n); bench/NOTES.md). Leaves the elements before that position in front of it and the
// rest behind, in no particular order within each part.
size_t weighted_cut(std::vector<std::pair<double, int32_t>>& keyed, const std::vector<Weight>& weight,
                    Weight total, int left, int count) {
  auto w = [&](size_t k) { return weight[size_t(keyed[k].second)]; };
  // (before + w / 2 < total left / count, in integers)
  auto short_of_target = [&](Weight before, Weight own) {
    return (2 * __int128(before) + own) * count < 2 * __int128(total) * left;
  };
  size_t lo = 0, hi = keyed.size();  // the cut lies in [lo, hi]
  Weight before = 0;                 // the weight in front of lo
  constexpr size_t kSortBelow = 64;
  while (hi - lo > kSortBelow) {
    const size_t mid = lo + (hi - lo) / 2;
    std::nth_element(keyed.begin() + std::ptrdiff_t(lo), keyed.begin() + std::ptrdiff_t(mid),
                     keyed.begin() + std::ptrdiff_t(hi));
    Weight sum = 0;
    for (size_t k = lo; k < mid; ++k) sum += w(k);
    if (short_of_target(before + sum, w(mid))) {
      before += sum + w(mid);
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  std::sort(keyed.begin() + std::ptrdiff_t(lo), keyed.begin() + std::ptrdiff_t(hi));
  size_t cut = lo;
  for (; cut < hi && short_of_target(before, w(cut)); ++cut) before += w(cut);
  return cut;
}

// Recursive coordinate bisection of `ids` over ranks [first, first + count): split across the
// box's longest side where the expected bonds divide as the ranks do, the particles ordered along
// the axis with ties by index (a strict total order, so the split does not depend on the order
// `ids` come in).
void bisect(const ParticleSet& ps, const std::vector<Weight>& weight, std::vector<int32_t> ids, int first,
            int count, Partition& out) {
  if (count == 1 || ids.empty()) {
    for (int32_t i : ids) out.owner[size_t(i)] = first;
    return;
  }
  Box box;
  for (int32_t i : ids) box.add(ps.rest[size_t(i)]);
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
  // (coordinate, index) pairs side by side rather than indices compared through the positions (a
  // cache miss per comparison at 10^7 particles).
  std::vector<std::pair<double, int32_t>> keyed(ids.size());
#pragma omp parallel for schedule(static)
  for (size_t k = 0; k < ids.size(); ++k) keyed[k] = {coordinate(ps.rest[size_t(ids[k])], axis), ids[k]};
  const int left = count / 2;
  Weight total = 0;
#pragma omp parallel for schedule(static) reduction(+ : total)
  for (size_t k = 0; k < ids.size(); ++k) total += weight[size_t(ids[k])];
  const size_t cut = weighted_cut(keyed, weight, total, left, count);
  ids = {};
  std::vector<int32_t> low(cut), high(keyed.size() - cut);
#pragma omp parallel for schedule(static)
  for (size_t k = 0; k < keyed.size(); ++k) (k < cut ? low[k] : high[k - cut]) = keyed[k].second;
  keyed = {};
  bisect(ps, weight, std::move(low), first, left, out);
  bisect(ps, weight, std::move(high), first + left, count - left, out);
}

// The bisection with the given weights, then every rank's ghosts and own particles.
Partition partition_by_weight(const ParticleSet& ps, const MaterialTable& mt, int ranks,
                              const std::vector<Weight>& weight) {
  const size_t n = ps.size();
  Partition p;
  p.ranks = ranks;
  p.owner.assign(n, 0);
  std::vector<int32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 0);
  bisect(ps, weight, std::move(ids), 0, ranks, p);

  // A rank's ghosts: every other rank's particle within the largest family radius (with room for
  // round-off) of the box around its own. A superset of the partners its families find.
  const double reach = longest_bond_bound(ps, mt);
  std::vector<Box> boxes(static_cast<size_t>(ranks));
  for (size_t i = 0; i < n; ++i) boxes[size_t(p.owner[i])].add(ps.rest[i]);
  p.ghosts.assign(size_t(ranks), {});
  std::vector<char> boundary(n, 0);  // a ghost of some rank
  for (size_t i = 0; i < n; ++i)
    for (int r = 0; r < ranks; ++r)
      if (r != p.owner[i] && boxes[size_t(r)].contains(ps.rest[i], reach)) {
        p.ghosts[size_t(r)].push_back(int32_t(i));
        boundary[i] = 1;
      }
  // Own particles, interior then boundary. A partner j of i (owned by another rank) lies within
  // the family radius of i, so i lies within reach of j's owner's box and is a ghost there: an
  // interior particle's partners are all its own rank's.
  p.owned.assign(size_t(ranks), {});
  p.interior.assign(size_t(ranks), 0);
  for (int pass = 0; pass < 2; ++pass)
    for (size_t i = 0; i < n; ++i)
      if (boundary[i] == pass) {
        p.owned[size_t(p.owner[i])].push_back(int32_t(i));
        if (pass == 0) ++p.interior[size_t(p.owner[i])];
      }
  return p;
}

}  // namespace

Partition partition_particles(const ParticleSet& ps, const MaterialTable& mt, int ranks) {
  std::vector<Weight> weight(ps.size());
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < ps.size(); ++i) weight[i] = bisection_weight(ps, mt, i);
  return partition_by_weight(ps, mt, ranks, weight);
}

Partition partition_particles(const ParticleSet& ps, const MaterialTable& mt, int ranks,
                              const std::vector<int32_t>& bonds) {
  std::vector<Weight> weight(ps.size());
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < ps.size(); ++i) weight[i] = Weight(bonds[i]) + 1;
  return partition_by_weight(ps, mt, ranks, weight);
}

RankLayout rank_layout(const Partition& p, int rank) {
  RankLayout l;
  l.rank = rank;
  const auto& own = p.owned[size_t(rank)];
  const auto& ghosts = p.ghosts[size_t(rank)];
  l.owned = int32_t(own.size());
  l.interior = p.interior[size_t(rank)];
  l.global = own;
  l.global.insert(l.global.end(), ghosts.begin(), ghosts.end());
  // Own particles by global index, for the send lists.
  std::vector<std::pair<int32_t, int32_t>> by_global(own.size());
  for (size_t k = 0; k < own.size(); ++k) by_global[k] = {own[k], int32_t(k)};
  std::sort(by_global.begin(), by_global.end());
  l.send.assign(size_t(p.ranks), {});
  l.recv.assign(size_t(p.ranks), {});
  for (int s = 0; s < p.ranks; ++s) {
    if (s == rank) continue;
    for (int32_t g : p.ghosts[size_t(s)])
      if (p.owner[size_t(g)] == rank)
        l.send[size_t(s)].push_back(
            std::lower_bound(by_global.begin(), by_global.end(), std::make_pair(g, int32_t(0)))->second);
  }
  for (size_t k = 0; k < ghosts.size(); ++k)
    l.recv[size_t(p.owner[size_t(ghosts[k])])].push_back(l.owned + int32_t(k));
  return l;
}

std::vector<uint64_t> local_face_bonds(const std::vector<uint64_t>& faces, const RankLayout& layout,
                                       size_t global_particles) {
  std::vector<uint64_t> local;
  if (faces.empty()) return local;
  std::vector<int32_t> local_of(global_particles, -1);
  for (size_t l = 0; l < layout.global.size(); ++l) local_of[size_t(layout.global[l])] = int32_t(l);
  for (const uint64_t key : faces) {
    const int32_t a = local_of[size_t(key >> 32)], b = local_of[size_t(key & 0xffffffffu)];
    if (a >= 0 && b >= 0) local.push_back(bond_key(a, b));
  }
  std::sort(local.begin(), local.end());
  return local;
}

ParticleSet local_particles(const ParticleSet& all, const RankLayout& layout) {
  ParticleSet ps;
  ps.reserve(layout.global.size());
  const bool anchors = all.anchor.size() == all.size();
  for (int32_t g : layout.global) {
    const size_t i = size_t(g);
    ps.add(all.rest[i], all.velocity[i], all.volume[i], all.mass[i], all.strain_limit0[i], all.material[i],
           all.body[i], all.flags[i], anchors ? all.anchor[i] : uint8_t(0));
    if (!all.shard.empty()) {
      ps.shard.push_back(all.shard[i]);
      ps.shard_strength.push_back(all.shard_strength[i]);
    }
  }
  return ps;
}

PartitionBalance partition_balance(const Partition& p, const ParticleSet& ps, const MaterialTable& mt) {
  PartitionBalance b;
  b.particles.assign(size_t(p.ranks), 0);
  b.ghosts.assign(size_t(p.ranks), 0);
  b.weight.assign(size_t(p.ranks), 0);
  for (int r = 0; r < p.ranks; ++r) {
    b.particles[size_t(r)] = int64_t(p.owned[size_t(r)].size());
    b.ghosts[size_t(r)] = int64_t(p.ghosts[size_t(r)].size());
    for (int32_t i : p.owned[size_t(r)]) b.weight[size_t(r)] += expected_bonds(ps, mt, size_t(i));
  }
  const double mean = std::accumulate(b.weight.begin(), b.weight.end(), 0.0) / double(p.ranks);
  b.imbalance = mean > 0 ? *std::max_element(b.weight.begin(), b.weight.end()) / mean : 1;
  return b;
}

}  // namespace pd
