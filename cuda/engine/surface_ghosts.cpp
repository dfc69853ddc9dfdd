#include "cuda/engine/surface_ghosts.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "cuda/engine/memory_budget.h"
#include "cuda/kernels/family.h"

namespace pd {

namespace {

// A stencil offset counts as present where a partner (or the particle itself) lies within this
// many of its sizes of it, a particle's size being the larger of the spacing and the cube root of
// its volume: on a lattice 0.75 spacings; scattered particles, whose typical nearest distance
// (the spacing, lambda) is well below their size (tets: their centroids sit at about 0.65 of it),
// cover the stencil points their volume holds, so that only those outside the body take ghosts.
constexpr double kCoverRadius = 0.75;
// A family whose fit matrix has an eigenvalue below this fraction of its largest does not span
// the quadratic basis (a plate or strand one or two particles thick): no ghosts.
constexpr double kThinFamily = 1e-9;
// A partner within this fraction of a spacing of a lattice point (per coordinate) is on it.
constexpr double kAligned = 0.05;
// A scattered particle whose family holds this fraction of the interior lattice family's volume
// (sum beta V) is inside the body: no ghosts.
constexpr double kInteriorVolume = 0.95;
// The largest sum of |coefficients| by which a ghost's displacement is extrapolated from the
// family that the quadratic fit may have: on lattices 17-20 at faces, edges and corners
// (delta = 3 lambda); a scattered family whose quadratic fit extrapolates wildly (which would
// shorten the stable step) takes the linear fit (exact under uniform strains, soft in bending).
constexpr double kMaxExtrapolation = 30;

// What the set-up finds for one particle with ghosts.
struct GhostRow {
  bool ghosted = false, thin = false, precracked = false, linear = false;
  std::vector<real> inverse;  // 81
  std::vector<real> moment;   // 9: A^-1 sum_k w_k p_k
  real inv_mw = 0;
  std::vector<Vec4> offset;
  std::vector<std::pair<int32_t, double>> rate;  // (particle, stability rate)
};

using Basis = Eigen::Matrix<double, kGhostBasis, 1>;

Basis basis_of(Vec3 xi, const Material& m) {
  real q[kGhostBasis];
  ghost_basis(xi, real(1) / m.horizon, q);
  Basis b;
  for (int a = 0; a < kGhostBasis; ++a) b[a] = double(q[a]);
  return b;
}

// The micromodulus the stability estimate takes (family.h stability_rate's).
double stability_micromodulus(const Material& m) {
  if (m.model != kStateBased) return double(m.micromodulus);
  const double k_eq = (double(m.bulk_modulus) + 4.0 * double(m.shear_modulus) / 3.0) / 1.8;
  const double d = double(m.horizon);
  return 18.0 * k_eq / (3.14159265358979323846 * d * d * d * d);
}

GhostRow ghost_row(int32_t i, const ParticleSet& ps, const MaterialTable& mt, const BondsView& b,
                   int32_t cut_count, const BodySolids* solids) {
  GhostRow row;
  const Material& m = mt.m[ps.material[i]];
  if (!m.ghost_correction) return row;
  if (cut_count != b.count[i]) {
    row.precracked = true;
    return row;
  }
  const double lambda = double(m.spacing), radius = double(m.family_radius()) * (1.0 + kHorizonSlack);
  const int reach = int(std::floor(radius / lambda)) + 1, side = 2 * reach + 1;
  std::vector<uint8_t> covered(size_t(side) * side * side, 0);
  auto cell = [&](int x, int y, int z) {
    return (size_t(z + reach) * side + size_t(y + reach)) * side + size_t(x + reach);
  };
  // The stencil points within kCoverRadius sizes of particle j (v: its offset in spacings).
  auto cover = [&](const Vec3& v, int32_t j) {
    const double size = std::max(1.0, std::cbrt(double(ps.volume[j])) / lambda), r = kCoverRadius * size;
    const int cx = int(std::lround(v.x)), cy = int(std::lround(v.y)), cz = int(std::lround(v.z));
    const int span = int(std::ceil(r));
    for (int z = cz - span; z <= cz + span; ++z)
      for (int y = cy - span; y <= cy + span; ++y)
        for (int x = cx - span; x <= cx + span; ++x) {
          if (std::abs(x) > reach || std::abs(y) > reach || std::abs(z) > reach) continue;
          const double dx = v.x - x, dy = v.y - y, dz = v.z - z;
          if (dx * dx + dy * dy + dz * dz < r * r) covered[cell(x, y, z)] = 1;
        }
  };
  const Vec3 rest_i = ps.rest[i];
  const int32_t count = b.count[i];
  bool aligned = true;     // every partner on a lattice point (within 5% of a spacing)
  double real_volume = 0;  // sum_j beta V_j
  for (int32_t k = 0; k < count; ++k) {
    const int32_t j = b.neighbor[b.slot(i, k)];
    real_volume += double(volume_fraction(length(ps.rest[j] - rest_i), m)) * double(ps.volume[j]);
    const Vec3 v = (ps.rest[j] - rest_i) * real(1.0 / lambda);
    aligned = aligned && std::fabs(v.x - std::round(v.x)) < kAligned &&
              std::fabs(v.y - std::round(v.y)) < kAligned && std::fabs(v.z - std::round(v.z)) < kAligned;
    cover(v, j);
  }
  cover({0, 0, 0}, i);
  if (!aligned && solids && solids->has(ps.body[i])) {
    // Where the body's solid is known, a stencil point is outside it or not: the rule above
    // leaves points inside a tet body bare between the tets' centroids, whose ghosts made the
    // bar too stiff (docs/validation.md, scattered particles).
    std::vector<uint8_t> inside(static_cast<size_t>(side));
    for (int z = -reach; z <= reach; ++z)
      for (int y = -reach; y <= reach; ++y) {
        solids->inside_along_x(ps.body[i], double(rest_i.x) - reach * lambda, lambda,
                               double(rest_i.y) + y * lambda, double(rest_i.z) + z * lambda, side,
                               inside.data());
        for (int x = -reach; x <= reach; ++x) covered[cell(x, y, z)] = inside[size_t(x + reach)];
      }
  }
  const double cube = lambda * lambda * lambda;
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        if ((x == 0 && y == 0 && z == 0) || covered[cell(x, y, z)]) continue;
        const double r0 = lambda * std::sqrt(double(x * x + y * y + z * z));
        if (r0 > radius) continue;
        row.offset.push_back({real(x * lambda), real(y * lambda), real(z * lambda),
                              real(double(volume_fraction(real(r0), m)) * cube)});
      }
  if (row.offset.empty()) return row;
  if (!aligned) {
    // Scattered particles (tets, Voronoi cells) are not where the stencil's points are, and a
    // stencil point inside the body may find no particle near it. A particle whose family holds
    // nearly the interior's volume is inside; near a surface the ghosts fill what its family
    // lacks of the interior's volume, their weights scaled to it.
    double interior = 0, ghosts = 0;
    for (int z = -reach; z <= reach; ++z)
      for (int y = -reach; y <= reach; ++y)
        for (int x = -reach; x <= reach; ++x) {
          const double r0 = lambda * std::sqrt(double(x * x + y * y + z * z));
          if (r0 > 0 && r0 <= radius) interior += double(volume_fraction(real(r0), m)) * cube;
        }
    for (const Vec4& o : row.offset) ghosts += double(o.w);
    if (real_volume >= kInteriorVolume * interior) {
      row.offset.clear();
      return row;
    }
    const double scale = (interior - real_volume) / ghosts;
    for (Vec4& o : row.offset) o.w = real(double(o.w) * scale);
  }
  // The fit over the family: A = sum_k w_k p_k p_k^T, with the kernels' float geometry.
  std::vector<Basis> wp(static_cast<size_t>(count));  // w_k p_k
  std::vector<int32_t> partner(static_cast<size_t>(count));
  Eigen::Matrix<double, kGhostBasis, kGhostBasis> a = Eigen::Matrix<double, kGhostBasis, kGhostBasis>::Zero();
  double m_real = 0;
  for (int32_t k = 0; k < count; ++k) {
    const int32_t j = b.neighbor[b.slot(i, k)];
    const Vec3 xi = ps.rest[j] - rest_i;
    const real r0 = length(xi);
    const double w = double(ghost_fit_weight(r0, ps.volume[j], m));
    const Basis p = basis_of(xi, m);
    a += w * p * p.transpose();
    wp[size_t(k)] = w * p;
    partner[size_t(k)] = j;
    m_real += w * double(r0) * double(r0);  // omega |xi|^2 beta V
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kGhostBasis, kGhostBasis>> eig(a);
  if (count < kGhostBasis || !(eig.eigenvalues()[0] > kThinFamily * eig.eigenvalues()[kGhostBasis - 1])) {
    row.offset.clear();
    row.thin = true;
    return row;
  }
  double m_ghost = 0;
  for (const Vec4& o : row.offset) {
    const double r0 = double(length(xyz(o)));
    m_ghost += double(m.horizon) * r0 * double(o.w);
  }
  row.inv_mw = real(1.0 / (m_real + m_ghost));
  // The stable step: ghost bond o is a spring of stiffness k_o (one end's share, half a bond's)
  // between i and the point sum_k a_ok x_k, a_ok = w_k p_k^T A^-1 p_o (and -sum_k a_ok on i); as
  // stability_rate counts a bond's stiffness once on each end, particle l takes k_o |a_ol| S_o / 2
  // with S_o = sum_l |a_ol| (the Gershgorin bound of the spring's stiffness matrix, halved).
  // Returns the largest S_o.
  const double c = stability_micromodulus(m), vol_i = double(ps.volume[i]);
  std::vector<double> share(static_cast<size_t>(count) + 1, 0.0);
  std::vector<double> coef(static_cast<size_t>(count));
  using Inverse = Eigen::Matrix<double, kGhostBasis, kGhostBasis>;
  auto stability_shares = [&](const Inverse& inv) {
    std::fill(share.begin(), share.end(), 0.0);
    double largest = 0;
    for (const Vec4& o : row.offset) {
      const double r0 = double(length(xyz(o)));
      const double k_o = 0.5 * c * double(o.w) * vol_i / r0;
      const Basis ainv_p = inv * basis_of(xyz(o), m);
      double on_i = 0, sum = 0;
      for (int32_t k = 0; k < count; ++k) {
        coef[size_t(k)] = wp[size_t(k)].dot(ainv_p);
        on_i -= coef[size_t(k)];
        sum += std::fabs(coef[size_t(k)]);
      }
      sum += std::fabs(on_i);
      largest = std::max(largest, sum);
      for (int32_t k = 0; k < count; ++k) share[size_t(k)] += 0.5 * k_o * std::fabs(coef[size_t(k)]) * sum;
      share[size_t(count)] += 0.5 * k_o * std::fabs(on_i) * sum;
    }
    return largest;
  };
  // The quadratic fit where its extrapolation stays moderate; else the linear one (its inverse
  // padded with zeros, so the kernels' quadratic coefficients come out 0).
  Inverse inv = a.inverse();
  if (stability_shares(inv) > kMaxExtrapolation) {
    inv.setZero();
    inv.topLeftCorner<3, 3>() = a.topLeftCorner<3, 3>().inverse();
    stability_shares(inv);
    row.linear = true;
  }
  row.ghosted = true;
  Basis sum = Basis::Zero();
  for (const Basis& v : wp) sum += v;
  const Basis moment = inv * sum;
  for (int r = 0; r < kGhostBasis; ++r) row.moment.push_back(real(moment[r]));
  row.inverse.resize(kGhostBasis * kGhostBasis);
  for (int r = 0; r < kGhostBasis; ++r)
    for (int q = 0; q < kGhostBasis; ++q) row.inverse[size_t(r * kGhostBasis + q)] = real(inv(r, q));
  for (int32_t k = 0; k < count; ++k) row.rate.emplace_back(partner[size_t(k)], share[size_t(k)]);
  row.rate.emplace_back(i, share[size_t(count)]);
  return row;
}

}  // namespace

GhostTables surface_ghosts(const ParticleSet& ps, const MaterialTable& mt, const BondLists& bonds,
                           const std::vector<int32_t>& cut_count, const BodySolids* solids) {
  const int32_t n = int32_t(ps.size());
  const BondsView b = bonds.view();
  std::vector<GhostRow> rows(static_cast<size_t>(n));
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < n; ++i) rows[size_t(i)] = ghost_row(i, ps, mt, b, cut_count[size_t(i)], solids);
  GhostTables t;
  t.of.assign(size_t(n), -1);
  t.stability_rate.assign(size_t(n), 0.0);
  t.first.push_back(0);
  t.push_first.push_back(0);
  int64_t pushed = 0;
  std::vector<uint8_t> receives(size_t(n), 0);
  for (int32_t i = 0; i < n; ++i) {
    GhostRow& r = rows[size_t(i)];
    t.thin += r.thin;
    t.linear += r.linear;
    t.precracked += r.precracked;
    if (!r.ghosted) continue;
    t.of[size_t(i)] = t.size();
    t.particle.push_back(i);
    t.inverse.insert(t.inverse.end(), r.inverse.begin(), r.inverse.end());
    t.moment.insert(t.moment.end(), r.moment.begin(), r.moment.end());
    t.inv_mw.push_back(r.inv_mw);
    t.offset.insert(t.offset.end(), r.offset.begin(), r.offset.end());
    t.first.push_back(int32_t(t.offset.size()));
    pushed += cut_count[size_t(i)];  // (a ghosted particle lost no bond to a cut)
    if (pushed > std::numeric_limits<int32_t>::max())
      throw ResourceError("the ghost surface correction holds at most 2^31 - 1 bonds of ghosted particles (" +
                          std::to_string(t.size()) +
                          " ghosted so far); set the materials' surface_correction to true (the factors) "
                          "or false, or lower --scale or the particle count");
    t.push_first.push_back(int32_t(pushed));
    for (const auto& [j, rate] : r.rate) {
      t.stability_rate[size_t(j)] += rate / double(ps.mass[size_t(j)]);
      receives[size_t(j)] = 1;
    }
    r = GhostRow();
  }
  for (int32_t i = 0; i < n; ++i)
    if (receives[size_t(i)]) t.receivers.push_back(i);
  return t;
}

double ghost_table_bytes(const GhostTables& t, int64_t slots) {
  const auto bytes = [](const auto& v) { return double(v.size()) * double(sizeof(v[0])); };
  return bytes(t.particle) + bytes(t.of) + bytes(t.first) + bytes(t.receivers) + bytes(t.push_first) +
         bytes(t.inverse) + bytes(t.moment) + bytes(t.inv_mw) + bytes(t.offset) +
         double(t.size()) * (kGhostPull * sizeof(real) + sizeof(uint8_t)) +  // pull, live
         double(t.push_first.back()) * double(sizeof(Vec4)) +                // push
         double(slots) * double(sizeof(int32_t));                            // mirror
}

void check_ghost_memory(const GhostTables& t, int64_t slots, Backend backend) {
  const double need = ghost_table_bytes(t, slots), free = double(backend_available_bytes(backend));
  if (need <= free) return;
  const bool gpu = backend == Backend::kCuda;
  throw ResourceError(
      "the ghost surface correction's tables (" + std::to_string(t.size()) + " ghosted particles, " +
      std::to_string(t.offset.size()) + " ghost bonds) need " + format_bytes(need) + " of " +
      (gpu ? "GPU" : "host") + " memory; " + format_bytes(free) +
      " are free. Set the materials' surface_correction to true (the factors) or " +
      "false, lower --scale or the particle count" + (gpu ? ", or run on a GPU with more memory" : ""));
}

}  // namespace pd
