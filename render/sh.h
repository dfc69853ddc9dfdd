// Order-2 real spherical harmonics (9 coefficients) and the irradiance environment map of
// Ramamoorthi & Hanrahan 2001, "An efficient representation for irradiance environment maps":
// project an environment's radiance onto Y_lm (l <= 2), then the irradiance at normal n is
// E(n) = sum_lm A_l L_lm Y_lm(n) with A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4 (their eq. 13).
#pragma once

#include <cmath>
#include <vector>

#include "render/geometry.h"

namespace pd {

// RGB coefficients L_lm in the order (0,0) (1,-1) (1,0) (1,1) (2,-2) (2,-1) (2,0) (2,1) (2,2).
struct Sh9 {
  Vec3 c[9];
};

// Y_lm(n) for a unit vector n, with the normalisation constants of RH01.
PD_HD inline void sh9_basis(Vec3 n, real y[9]) {
  y[0] = real(0.282094792);  // 1 / (2 sqrt(pi))
  y[1] = real(0.488602512) * n.y;
  y[2] = real(0.488602512) * n.z;
  y[3] = real(0.488602512) * n.x;
  y[4] = real(1.092548431) * n.x * n.y;
  y[5] = real(1.092548431) * n.y * n.z;
  y[6] = real(0.315391565) * (3 * n.z * n.z - 1);
  y[7] = real(1.092548431) * n.x * n.z;
  y[8] = real(0.546274215) * (n.x * n.x - n.y * n.y);
}

// RH01 eq. 13: irradiance at unit normal n from the coefficients L.
PD_HD inline Vec3 sh9_irradiance(const Sh9& L, Vec3 n) {
  const real c1 = real(0.429043), c2 = real(0.511664), c3 = real(0.743125), c4 = real(0.886227),
             c5 = real(0.247708);
  const real x = n.x, y = n.y, z = n.z;
  return (c1 * (x * x - y * y)) * L.c[8] + (c3 * z * z - c5) * L.c[6] + c4 * L.c[0] +
         (2 * c1) * (x * y * L.c[4] + x * z * L.c[7] + y * z * L.c[5]) +
         (2 * c2) * (x * L.c[3] + y * L.c[1] + z * L.c[2]);
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton iteration on P_n), host only.
inline void gauss_legendre(int n, double* node, double* weight) {
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1, p1 = x;  // P_0, P_1, then P_{k-1}, P_k
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-15) break;
    }
    node[i] = x;
    weight[i] = 2 / ((1 - x * x) * dp * dp);
  }
}

// L_lm = integral of radiance(w) Y_lm(w) over the sphere: Gauss-Legendre in z = cos(theta)
// (n_z nodes) times the midpoint rule in phi (2 n_z nodes). Exact for constant and
// low-order polynomial radiance. Host only; `radiance` maps a unit vector to linear RGB.
template <class Radiance>
Sh9 project_sh9(const Radiance& radiance, int n_z = 96) {
  const double pi = 3.14159265358979323846;
  std::vector<double> node(n_z), weight(n_z);
  gauss_legendre(n_z, node.data(), weight.data());
  const int n_phi = 2 * n_z;
  const double d_phi = 2 * pi / n_phi;
  double sum[9][3] = {};
  for (int i = 0; i < n_z; ++i) {
    const double z = node[i], s = std::sqrt(1 - z * z);
    for (int j = 0; j < n_phi; ++j) {
      const double phi = (j + 0.5) * d_phi;
      const Vec3 w{real(s * std::cos(phi)), real(s * std::sin(phi)), real(z)};
      const Vec3 L = radiance(w);
      real y[9];
      sh9_basis(w, y);
      const double dw = weight[i] * d_phi;
      for (int k = 0; k < 9; ++k) {
        sum[k][0] += dw * y[k] * L.x;
        sum[k][1] += dw * y[k] * L.y;
        sum[k][2] += dw * y[k] * L.z;
      }
    }
  }
  Sh9 out;
  for (int k = 0; k < 9; ++k) out.c[k] = {real(sum[k][0]), real(sum[k][1]), real(sum[k][2])};
  return out;
}

}  // namespace pd
