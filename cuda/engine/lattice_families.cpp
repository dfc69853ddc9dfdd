#include "cuda/engine/lattice_families.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <parallel/algorithm>  // __gnu_parallel::sort (OpenMP)
#include <stdexcept>
#include <string>
#include <utility>

#include "cuda/engine/bond_cuts.h"
#include "cuda/kernels/bond.h"

namespace pd {

namespace {

// A body's particles [first, first + nx ny nz) on the grid origin + (ix, iy, iz) h.
struct BoxGrid {
  int32_t first = 0;
  std::array<int32_t, 3> n{};
  std::array<double, 3> origin{}, h{};
  std::array<int32_t, 3> coords(int32_t i) const {
    const int32_t r = i - first;
    return {r % n[0], (r / n[0]) % n[1], r / (n[0] * n[1])};
  }
};

double axis(const Vec3& v, int a) {
  return a == 0 ? v.x : (a == 1 ? v.y : v.z);
}

// The box grid of the contiguous particles [first, end), if they form one (see the header).
bool find_box_grid(const ParticleSet& ps, int32_t first, int32_t end, BoxGrid& g) {
  const int32_t count = end - first;
  const Vec3 p0 = ps.rest[size_t(first)];
  int32_t nx = 1, ny = 1;
  while (nx < count && ps.rest[size_t(first + nx)].y == p0.y && ps.rest[size_t(first + nx)].z == p0.z) ++nx;
  while (int64_t(ny) * nx < count && ps.rest[size_t(first + ny * nx)].z == p0.z) ++ny;
  if (count % (nx * ny) != 0) return false;
  g.first = first;
  g.n = {nx, ny, count / (nx * ny)};
  if (g.n[0] < 2 || g.n[1] < 2 || g.n[2] < 2) return false;
  const int32_t last_along[3] = {first + nx - 1, first + (ny - 1) * nx, first + (g.n[2] - 1) * nx * ny};
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = axis(p0, a);
    g.h[a] = (axis(ps.rest[size_t(last_along[a])], a) - g.origin[a]) / (g.n[a] - 1);
    if (!(g.h[a] > 0)) return false;
  }
  const double tol = 1e-3 * std::min({g.h[0], g.h[1], g.h[2]});
  for (int32_t i = first; i < end; ++i) {
    if (ps.material[size_t(i)] != ps.material[size_t(first)] ||
        ps.volume[size_t(i)] != ps.volume[size_t(first)])
      return false;
    const auto c = g.coords(i);
    for (int a = 0; a < 3; ++a)
      if (std::abs(axis(ps.rest[size_t(i)], a) - (g.origin[a] + c[a] * g.h[a])) > tol) return false;
  }
  return true;
}

// The families a stencil is made from, as rows of the tables: row r is the whole run's particle
// gid(r), whose partners' whole-run indices and intact flags partner(r, k) gives in family order
// (one run: every particle, row = index; a partitioned rank: its own particles of the body, rows
// in its local order). Partner is a callable, inlined into add_stencil's loops over every bond.
template <class Partner>
struct BodyRows {
  std::vector<int32_t> rows, gids;  // the body's particles: their rows and whole-run indices
  const int32_t* count = nullptr;   // per row: its family's size
  Partner partner;                  // (row, k) -> whole-run index, ~index if broken
};

// Builds body `g`'s stencil from its families and sets its rows' bits; false (nothing changed)
// when the families do not fit a stencil. Bonds are identified by their index offset j - i alone
// (no division per bond): no bond is longer than the family radius, so along each axis it spans
// at most `bound` cells, and a grid wider than 2 bound along x and y gives every such cell offset
// its own index offset. With `reduce` (a partitioned rank) the fit and the offsets used are
// combined over the ranks, so every rank builds the stencil one run builds.
template <class Partner>
bool add_stencil(const ParticleSet& ps, const Material& m, const BoxGrid& g, const BodyRows<Partner>& body,
                 LatticeFamilies& lf, StencilReduce* reduce) {
  std::array<int32_t, 3> bound{};
  for (int a = 0; a < 3; ++a) bound[a] = int32_t(std::floor(double(m.family_radius()) * (1 + 1e-4) / g.h[a]));
  if (g.n[0] <= 2 * bound[0] || g.n[1] <= 2 * bound[1] || bound[0] > 127 || bound[1] > 127 || bound[2] > 127)
    return false;
  const int64_t reach = bound[0] + int64_t(g.n[0]) * (bound[1] + int64_t(g.n[1]) * bound[2]);
  if (reach > (int64_t(1) << 28)) return false;
  const int32_t end = g.first + g.n[0] * g.n[1] * g.n[2];
  // The cell offset d of each index offset within reach (offset + reach indexes these arrays).
  const size_t span = size_t(2 * reach + 1);
  std::vector<std::array<int8_t, 3>> cells(span);
  std::vector<uint8_t> is_cell(span, 0), used(span, 0);
  for (int32_t dz = -bound[2]; dz <= bound[2]; ++dz)
    for (int32_t dy = -bound[1]; dy <= bound[1]; ++dy)
      for (int32_t dx = -bound[0]; dx <= bound[0]; ++dx) {
        const size_t at = size_t(reach + dx + int64_t(g.n[0]) * (dy + int64_t(g.n[1]) * dz));
        cells[at] = {int8_t(dx), int8_t(dy), int8_t(dz)};
        is_cell[at] = 1;
      }
  // The offsets the families use: partners in the body, ascending, within the bounds.
  bool fits = true;
  const int32_t rows = int32_t(body.rows.size());
#pragma omp parallel for schedule(static) reduction(&& : fits)
  for (int32_t r = 0; r < rows; ++r) {
    const int32_t row = body.rows[size_t(r)], i = body.gids[size_t(r)];
    int32_t previous = -1;
    for (int32_t k = 0; k < body.count[row] && fits; ++k) {
      const int32_t j = bond_partner(body.partner(row, k));
      const int64_t at = reach + (j - i);
      // Another body, not ascending, or beyond the bounds.
      fits = j >= g.first && j < end && j > previous && at >= 0 && at < int64_t(span) && is_cell[size_t(at)];
      previous = j;
      if (fits) {
#pragma omp atomic write
        used[size_t(at)] = 1;
      }
    }
  }
  if (reduce) {
    if (!reduce->all(fits)) return false;
    std::vector<int32_t> mine;
    for (size_t at = 0; at < span; ++at)
      if (used[at]) mine.push_back(int32_t(at));
    for (int32_t at : reduce->union_of(mine)) used[size_t(at)] = 1;
  }
  if (!fits) return false;
  const int64_t size = std::count(used.begin(), used.end(), uint8_t(1));
  if (size > 32 * kLatticeWords || lf.stencils.size() >= size_t(std::numeric_limits<int16_t>::max()))
    return false;

  // The stencil in ascending offset, the order of ascending partners.
  Stencil st;
  st.first = int32_t(lf.entries.size());
  st.size = int32_t(size);
  std::vector<int32_t> entry_of(span, -1);
  for (size_t at = 0; at < span; ++at) {
    if (!used[at]) continue;
    const auto& d = cells[at];
    StencilEntry e{};
    e.xi = {real(d[0] * g.h[0]), real(d[1] * g.h[1]), real(d[2] * g.h[2]), 0};
    const double r0 = std::sqrt(double(e.xi.x) * e.xi.x + double(e.xi.y) * e.xi.y + double(e.xi.z) * e.xi.z);
    e.xi.w = real(r0);
    e.inv_r0 = real(1.0 / r0);
    e.weight = volume_fraction(e.xi.w, m) * ps.volume[size_t(g.first)];  // as bond_geometry computes it
    e.offset = int32_t(int64_t(at) - reach);
    entry_of[at] = int32_t(lf.entries.size()) - st.first;
    lf.entries.push_back(e);
  }
  const int16_t id = int16_t(lf.stencils.size());
  lf.stencils.push_back(st);

  // Per row: grow the masks to the stencil's words, then set its bits.
  const int32_t words = int32_t(size + 31) / 32;
  if (words > lf.words) {
    const size_t n = lf.stencil.size();
    lf.present.resize(size_t(words) * n, 0);
    lf.intact.resize(size_t(words) * n, 0);
    lf.words = words;
  }
  const size_t n = lf.stencil.size();
#pragma omp parallel for schedule(static)  // each row sets only its own words
  for (int32_t r = 0; r < rows; ++r) {
    const int32_t row = body.rows[size_t(r)], i = body.gids[size_t(r)];
    lf.stencil[size_t(row)] = id;
    for (int32_t k = 0; k < body.count[row]; ++k) {
      const int32_t nb = body.partner(row, k);
      const int32_t q = entry_of[size_t(reach + (bond_partner(nb) - i))];
      const size_t word = size_t(q / 32) * n + size_t(row);
      lf.present[word] |= 1u << (q % 32);
      if (bond_intact(nb)) lf.intact[word] |= 1u << (q % 32);
    }
  }
  return true;
}

// On a partitioned rank, after add_stencil gave the body its stencil `id` (partners as the whole
// run's offsets, which are not the rank's): that stencil becomes `listed`, and a copy with the
// rank's own offsets serves the rows whose present partners all sit at them. Each entry's offset
// is the one most rows with every entry present agree on (a sample of them, spread over the
// body's rows): in a part of the layout ordered as a box grid (the interior, then the boundary,
// each by global index) a row whose partner lies in another part finds it elsewhere, each at
// its own distance, while the rows of the part agree. Every row is then checked against the
// offsets, so any layout is served correctly, box-shaped parts well.
void add_local_stencil(LatticeFamilies& lf, int16_t id, std::vector<int32_t> rows, const BondsView& v) {
  const Stencil st = lf.stencils[size_t(id)];
  lf.stencils[size_t(id)].listed = 1;
  if (rows.empty() || lf.stencils.size() >= size_t(std::numeric_limits<int16_t>::max())) return;
  std::sort(rows.begin(), rows.end());
  const size_t n = lf.stencil.size();
  const auto full = [&](int32_t row) {
    for (int32_t q = 0; q < st.size; ++q)
      if (!(lf.present[size_t(q / 32) * n + size_t(row)] >> (q % 32) & 1u)) return false;
    return true;
  };
  // Whether row's present partners sit at `offset`.
  const auto fits = [&](int32_t row, const std::vector<int32_t>& offset) {
    int32_t k = 0;
    for (int32_t q = 0; q < st.size; ++q) {
      if (!(lf.present[size_t(q / 32) * n + size_t(row)] >> (q % 32) & 1u)) continue;
      const int64_t j = int64_t(row) + offset[size_t(q)];
      if (j < 0 || j >= int64_t(n) || bond_partner(v.neighbor[v.slot(row, k++)]) != j) return false;
    }
    return true;
  };
  const int32_t count = int32_t(rows.size());
  std::vector<int32_t> sample;
  const int32_t stride = std::max(1, count / 4096);
  for (int32_t r = 0; r < count; r += stride)
    if (full(rows[size_t(r)])) sample.push_back(rows[size_t(r)]);
  if (sample.empty()) return;
  std::vector<int32_t> best(size_t(st.size)), seen(sample.size());
  for (int32_t q = 0; q < st.size; ++q) {
    for (size_t s = 0; s < sample.size(); ++s)
      seen[s] = bond_partner(v.neighbor[v.slot(sample[s], q)]) - sample[s];
    std::sort(seen.begin(), seen.end());
    size_t most = 0;
    for (size_t s = 0, t = 0; s < seen.size(); s = t) {
      for (t = s; t < seen.size() && seen[t] == seen[s]; ++t) {
      }
      if (t - s > most) most = t - s, best[size_t(q)] = seen[s];
    }
  }
  int32_t best_fit = 0;
#pragma omp parallel for schedule(static) reduction(+ : best_fit)
  for (int32_t r = 0; r < count; ++r) best_fit += fits(rows[size_t(r)], best);
  if (best_fit == 0) return;
  const int16_t local = int16_t(lf.stencils.size());
  Stencil copy = st;
  copy.first = int32_t(lf.entries.size());
  copy.listed = 0;
  lf.stencils.push_back(copy);
  for (int32_t q = 0; q < st.size; ++q) {
    StencilEntry e = lf.entries[size_t(st.first + q)];
    e.offset = best[size_t(q)];
    lf.entries.push_back(e);
  }
#pragma omp parallel for schedule(static)
  for (int32_t r = 0; r < count; ++r)
    if (fits(rows[size_t(r)], best)) lf.stencil[size_t(rows[size_t(r)])] = local;
}

// Each body of `ps` whose particles are contiguous, as [first, end).
std::vector<std::pair<int32_t, int32_t>> contiguous_bodies(const ParticleSet& ps) {
  const int32_t n = int32_t(ps.size());
  std::map<int32_t, std::pair<int32_t, int32_t>> range;  // body -> [first, end)
  std::map<int32_t, bool> contiguous;
  for (int32_t i = 0; i < n; ++i) {
    const int32_t body = ps.body[size_t(i)];
    auto it = range.find(body);
    if (it == range.end()) {
      range[body] = {i, i + 1};
      contiguous[body] = true;
    } else if (it->second.second == i) {
      it->second.second = i + 1;
    } else {
      contiguous[body] = false;
    }
  }
  std::vector<std::pair<int32_t, int32_t>> out;
  for (const auto& [body, r] : range)
    if (contiguous[body]) out.push_back(r);
  return out;
}

}  // namespace

int64_t LatticeFamilies::particles() const {
  return std::count_if(stencil.begin(), stencil.end(), [](int16_t s) { return s >= 0; });
}

int64_t LatticeFamilies::listed_particles() const {
  return std::count_if(stencil.begin(), stencil.end(),
                       [&](int16_t s) { return s >= 0 && stencils[size_t(s)].listed; });
}

int64_t box_grid_particles(const ParticleSet& ps) {
  int64_t count = 0;
  for (const auto& [first, end] : contiguous_bodies(ps)) {
    BoxGrid g;
    if (find_box_grid(ps, first, end, g)) count += end - first;
  }
  return count;
}

LatticeFamilies lattice_families(const ParticleSet& ps, const MaterialTable& mt, const BondLists& bonds) {
  LatticeFamilies lf;
  lf.stencil.assign(ps.size(), -1);
  const BondsView v = bonds.view();
  for (const auto& [first, end] : contiguous_bodies(ps)) {
    BoxGrid g;
    if (!find_box_grid(ps, first, end, g)) continue;
    const auto partner = [&](int32_t i, int32_t k) { return v.neighbor[v.slot(i, k)]; };
    BodyRows<decltype(partner)> body{{}, {}, v.count.data(), partner};
    for (int32_t i = first; i < end; ++i) body.rows.push_back(i);
    body.gids = body.rows;
    add_stencil(ps, mt.m[ps.material[size_t(g.first)]], g, body, lf, nullptr);
  }
  return lf;
}

LatticeFamilies rank_lattice_families(const ParticleSet& ps, const MaterialTable& mt, const BondLists& local,
                                      const std::vector<int32_t>& global, int32_t owned,
                                      StencilReduce& reduce) {
  LatticeFamilies lf;
  lf.stencil.assign(global.size(), -1);
  const BondsView v = local.view();
  // The rank's own particles by whole-run index, to find each body's.
  std::vector<std::pair<int32_t, int32_t>> own(static_cast<size_t>(owned));
  for (int32_t i = 0; i < owned; ++i) own[size_t(i)] = {global[size_t(i)], i};
  std::sort(own.begin(), own.end());
  for (const auto& [first, end] : contiguous_bodies(ps)) {
    BoxGrid g;
    if (!find_box_grid(ps, first, end, g)) continue;
    const auto partner = [&](int32_t row, int32_t k) {
      const int32_t nb = v.neighbor[v.slot(row, k)];
      const int32_t j = global[size_t(bond_partner(nb))];
      return bond_intact(nb) ? j : ~j;
    };
    BodyRows<decltype(partner)> body{{}, {}, v.count.data(), partner};
    for (auto it = std::lower_bound(own.begin(), own.end(), std::make_pair(first, int32_t(0)));
         it != own.end() && it->first < end; ++it) {
      body.rows.push_back(it->second);
      body.gids.push_back(it->first);
    }
    if (add_stencil(ps, mt.m[ps.material[size_t(g.first)]], g, body, lf, &reduce))
      add_local_stencil(lf, int16_t(lf.stencils.size() - 1), body.rows, v);
  }
  return lf;
}

// Calls f(q, word, bit, k) for each stencil entry q that lattice particle i's family holds: its
// mask word's index, the entry's bit in it, and the bond's position k in the family.
template <class F>
void for_each_present_bond(const LatticeFamilies& lf, int32_t i, F f) {
  const size_t n = lf.stencil.size();
  const Stencil& st = lf.stencils[size_t(lf.stencil[size_t(i)])];
  int32_t k = 0;
  for (int32_t q = 0; q < st.size; ++q) {
    const size_t word = size_t(q / 32) * n + size_t(i);
    const uint32_t bit = 1u << (q % 32);
    if (lf.present[word] & bit) f(q, word, bit, k++);
  }
}

void mark_weak_lattice_bonds(LatticeFamilies& lf, const BondLists& bonds,
                             const std::vector<uint8_t>& strength) {
  const BondsView v = bonds.view();
  lf.weak.assign(lf.present.size(), 0);
#pragma omp parallel for schedule(static)  // each particle sets only its own words
  for (int32_t i = 0; i < int32_t(lf.stencil.size()); ++i) {
    if (lf.stencil[size_t(i)] < 0) continue;
    for_each_present_bond(lf, i, [&](int32_t, size_t word, uint32_t bit, int32_t k) {
      if (strength[size_t(v.slot(i, k))] < kStrengthLevels) lf.weak[word] |= bit;
    });
  }
}

SurfaceRows surface_rows(const LatticeFamilies& lf, const BondLists& bonds,
                         const std::vector<uint16_t>& surface_bond) {
  const BondsView v = bonds.view();
  const int32_t n = int32_t(lf.stencil.size());
  // Calls f(q, x) for each entry q of lattice particle i's stencil, x its bond's factor (0 where
  // its family lacks the entry): the particle's row.
  const auto for_each_in_row = [&](int32_t i, auto f) {
    const int32_t size = lf.stencils[size_t(lf.stencil[size_t(i)])].size;
    int32_t k = 0;
    for (int32_t q = 0; q < size; ++q)
      f(q, lf.present[size_t(q / 32) * size_t(n) + size_t(i)] >> (q % 32) & 1u
               ? surface_bond[size_t(v.slot(i, k++))]
               : uint16_t(0));
  };
  const auto row_of = [&](int32_t i, std::vector<uint16_t>& row) {
    row.assign(size_t(lf.stencils[size_t(lf.stencil[size_t(i)])].size), 0);
    for_each_in_row(i, [&](int32_t q, uint16_t x) { row[size_t(q)] = x; });
  };
  // Rows hashed (FNV-1a) in parallel and sorted by (hash, particle): each particle's
  // representative is the first particle of its hash, checked equal in parallel (a particle
  // whose row differs, a hash collision, is its own representative).
  std::vector<std::pair<uint64_t, int32_t>> keyed;
  keyed.reserve(size_t(n));
  for (int32_t i = 0; i < n; ++i)
    if (lf.stencil[size_t(i)] >= 0) keyed.push_back({0, i});
  const int64_t lattice = int64_t(keyed.size());
#pragma omp parallel for schedule(static)
  for (int64_t e = 0; e < lattice; ++e) {
    uint64_t h = 1469598103934665603ull;
    for_each_in_row(keyed[size_t(e)].second, [&](int32_t, uint16_t x) { h = (h ^ x) * 1099511628211ull; });
    keyed[size_t(e)].first = h;
  }
  __gnu_parallel::sort(keyed.begin(), keyed.end());
  // Per entry its hash's ordinal; per ordinal the first particle and its row.
  std::vector<int32_t> ordinal(static_cast<size_t>(lattice)), head;
  for (int64_t e = 0; e < lattice; ++e) {
    if (e == 0 || keyed[size_t(e - 1)].first != keyed[size_t(e)].first)
      head.push_back(keyed[size_t(e)].second);
    ordinal[size_t(e)] = int32_t(head.size()) - 1;
  }
  std::vector<std::vector<uint16_t>> head_row(head.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (size_t o = 0; o < head.size(); ++o) row_of(head[o], head_row[o]);
  std::vector<int32_t> rep(size_t(n), -1);
#pragma omp parallel for schedule(static)
  for (int64_t e = 0; e < lattice; ++e) {
    const int32_t i = keyed[size_t(e)].second, o = ordinal[size_t(e)];
    const std::vector<uint16_t>& first = head_row[size_t(o)];
    bool same = lf.stencils[size_t(lf.stencil[size_t(i)])].size == int32_t(first.size());
    if (same && i != head[size_t(o)])
      for_each_in_row(i, [&](int32_t q, uint16_t x) { same = same && first[size_t(q)] == x; });
    rep[size_t(i)] = same ? head[size_t(o)] : i;
  }
  // Rows stored in the order of their first particle; each particle points at its
  // representative's.
  SurfaceRows out;
  out.row.assign(size_t(n), -1);
  std::vector<uint16_t> row;
  for (int32_t i = 0; i < n; ++i) {
    if (rep[size_t(i)] < 0) continue;
    if (rep[size_t(i)] == i) {
      row_of(i, row);
      if (out.table.size() + row.size() > size_t(std::numeric_limits<int32_t>::max()))
        throw std::length_error("the surface correction's table of lattice rows outgrew 2^31 entries");
      out.row[size_t(i)] = int32_t(out.table.size());
      out.table.insert(out.table.end(), row.begin(), row.end());
      ++out.rows;
    } else {
      out.row[size_t(i)] = out.row[size_t(rep[size_t(i)])];
    }
  }
  return out;
}

void refresh_lattice_intact(LatticeFamilies& lf, const BondLists& bonds) {
  const BondsView v = bonds.view();
  for (int32_t i = 0; i < int32_t(lf.stencil.size()); ++i) {
    const int32_t s = lf.stencil[size_t(i)];
    if (s < 0) continue;
    auto differ = [&]() {
      return std::invalid_argument("the restored families differ from the engine's at particle " +
                                   std::to_string(i) + " (a snapshot of another scene or version)");
    };
    const Stencil& st = lf.stencils[size_t(s)];
    int32_t listed = 0;
    for_each_present_bond(lf, i, [&](int32_t q, size_t word, uint32_t bit, int32_t k) {
      const int32_t nb = k < v.count[i] ? v.neighbor[v.slot(i, k)] : -1;
      if (k >= v.count[i] || (!st.listed && bond_partner(nb) != i + lf.entries[size_t(st.first + q)].offset))
        throw differ();
      lf.intact[word] = bond_intact(nb) ? lf.intact[word] | bit : lf.intact[word] & ~bit;
      listed = k + 1;
    });
    if (listed != v.count[i]) throw differ();
  }
}

}  // namespace pd
