// One interior particle of a simple-cubic lattice and its whole family, under a homogeneous
// deformation u = F X. Every particle of an infinite lattice then sees the same state, so the
// kernel bodies evaluated for this particle give the material's exact discrete response:
// dilatation, plastic history, and the stress sigma = 1/2 sum_j (t_ij + t_ji) beta V_j y^ (x) xi.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "cuda/kernels/plasticity.h"
#include "cuda/kernels/springforces_state.h"
#include "tests/support/particle_arrays.h"

namespace pd::testing {

using Mat3 = std::array<std::array<double, 3>, 3>;

struct InteriorParticle : ParticleArrays {
  Material m;
  std::vector<int32_t> count, neighbor;
  std::vector<int64_t> offset;
  std::vector<real> plastic;

  // Lattice of spacing 1, horizon `ratio`; centre particle 0, its family 1..N (the
  // material's family radius, as the engine builds it).
  InteriorParticle(Material mat, double ratio) : m(mat) {
    m.spacing = 1;
    m.horizon = real(ratio);
    const double radius = m.family_radius();
    rest.push_back({0, 0, 0, 1});
    const int r = int(std::ceil(radius));
    for (int z = -r; z <= r; ++z)
      for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x) {
          const double d2 = double(x) * x + double(y) * y + double(z) * z;
          if (d2 > 0 && d2 <= radius * radius * (1 + 1e-9)) rest.push_back({real(x), real(y), real(z), 1});
        }
    const size_t n = rest.size();
    disp.assign(n, {0, 0, 0, real(1e30)});  // w: strain limit, never reached
    state.assign(n, {0, 0, 0, 0});
    vel = force = std::vector<Vec3>(n, Vec3{0, 0, 0});
    inv_mass.assign(n, 1);
    smin.assign(n, 0);
    tau0.assign(n, real(1e30));
    material.assign(n, 0);
    body.assign(n, 0);
    flags.assign(n, 0);
    ledger.assign(n, Ledger());
    count.assign(n, 0);
    count[0] = int32_t(n - 1);
    intact = count;
    const size_t slices = (n + kSliceWidth - 1) / kSliceWidth;
    offset.assign(slices + 1, int64_t(slices) * 0);
    // Only particle 0 has bonds: its slice holds them, the other slices are empty.
    offset[0] = 0;
    for (size_t s = 1; s <= slices; ++s) offset[s] = int64_t(n - 1) * kSliceWidth;
    neighbor.assign(size_t(n - 1) * kSliceWidth, 0);
    plastic.assign(neighbor.size(), 0);
    for (int32_t k = 0; k + 1 < int32_t(n); ++k) neighbor[size_t(k) * kSliceWidth] = k + 1;
    table.count = 1;
    table.m[0] = m;
    weighted_volume(0, view(), bonds(), table);
    for (auto& s : state) s.y = state[0].y;
  }

  MaterialTable table;

  BondsView bonds() {
    BondsView b;
    b.n = int32_t(rest.size());
    b.slice_offset = view_of(offset);
    b.count = view_of(count);
    b.neighbor = view_of(neighbor);
    b.plastic = view_of(plastic);
    return b;
  }
  int32_t family_size() const { return count[0]; }
  double theta() const { return state[0].x; }

  // u = F X, then theta (the same everywhere) and the plastic return mapping at particle 0.
  void deform(const Mat3& grad) {
    for (size_t i = 0; i < rest.size(); ++i) {
      const Vec4 x = rest[i];
      disp[i] = {real(grad[0][0] * x.x + grad[0][1] * x.y + grad[0][2] * x.z),
                 real(grad[1][0] * x.x + grad[1][1] * x.y + grad[1][2] * x.z),
                 real(grad[2][0] * x.x + grad[2][1] * x.y + grad[2][2] * x.z), disp[i].w};
    }
    const DilatationPass d = dilatation<true, true, true>(0, view(), bonds(), m);
    for (auto& s : state) s.x = d.theta;
    state[0].w = d.trial_norm;
    yield_test(0, view(), table);
    if (!m.plastic || state[0].w >= real(1)) return;
    const BondsView b = bonds();
    for (int32_t k = 0; k < count[0]; ++k) {
      const int64_t slot = b.slot(0, k);
      const BondGeometry g = bond_geometry(rest[0], disp[0], rest[neighbor[slot]], disp[neighbor[slot]]);
      plastic[slot] = returned_plastic_extension(g.e, g.r0, state[0].x, state[0].w, plastic[slot], m);
    }
  }

  // By symmetry t_ji on bond -xi equals t_ij on xi, so sigma = sum_j t_ij beta V_j y^ (x) xi.
  Mat3 stress() {
    Mat3 s{};
    const BondsView b = bonds();
    for (int32_t k = 0; k < count[0]; ++k) {
      const int64_t slot = b.slot(0, k);
      const BondGeometry g = bond_geometry(rest[0], disp[0], rest[neighbor[slot]], disp[neighbor[slot]]);
      const double t =
          force_state(influence(g.xi, g.inv_r0, m), g.r0, g.e, state[0].x, state[0].y, plastic[slot], m);
      const double w = t * volume_fraction(g.r0, m) * g.inv_r;
      const double y[3] = {g.y.x, g.y.y, g.y.z}, xi[3] = {g.xi.x, g.xi.y, g.xi.z};
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) s[a][c] += w * y[a] * xi[c];
    }
    return s;
  }
};

// An isotropic state-based material from Young's modulus and Poisson ratio.
inline Material state_material(double youngs, double poisson, double horizon_ratio = 3, bool partial = true) {
  Material m;
  m.model = kStateBased;
  m.bulk_modulus = real(youngs / (3 * (1 - 2 * poisson)));
  m.shear_modulus = real(youngs / (2 * (1 + poisson)));
  m.horizon = real(horizon_ratio);
  m.spacing = 1;
  m.partial_volumes = partial ? 1 : 0;
  return m;
}

}  // namespace pd::testing
