// Dielectric Fresnel (render/fresnel.h): R + T = 1 from independent amplitude formulas, known
// values, total internal reflection, Snell's law of the refracted direction.
#include <gtest/gtest.h>

#include <cmath>

#include "render/fresnel.h"

namespace pd {
namespace {

TEST(Fresnel, ReflectanceAndTransmittanceAddUpToOne) {
  // Air -> glass and glass -> air, every angle below the critical one.
  for (const auto& [n1, n2] : {std::pair<real, real>{1, real(1.5)}, {real(1.5), 1}, {1, real(2.4)}}) {
    for (int k = 0; k <= 200; ++k) {
      const real cos_i = real(k) / 200;
      const Fresnel f = fresnel_dielectric(cos_i, n1, n2);
      if (f.transmit == 0) {
        EXPECT_EQ(f.reflect, 1) << "n1=" << n1 << " cos_i=" << cos_i;
        continue;
      }
      EXPECT_NEAR(f.reflect + f.transmit, 1, 2e-6) << "n1=" << n1 << " n2=" << n2 << " cos_i=" << cos_i;
      EXPECT_GE(f.reflect, 0);
      EXPECT_GE(f.transmit, 0);
    }
  }
}

TEST(Fresnel, KnownValues) {
  // Normal incidence: ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass, from either side.
  EXPECT_NEAR(fresnel_dielectric(1, 1, real(1.5)).reflect, 0.04, 1e-6);
  EXPECT_NEAR(fresnel_dielectric(1, real(1.5), 1).reflect, 0.04, 1e-6);
  // Grazing incidence reflects everything.
  EXPECT_NEAR(fresnel_dielectric(0, 1, real(1.5)).reflect, 1, 1e-6);
  // At Brewster's angle tan(theta) = n2 / n1 the p part vanishes: R = Rs / 2.
  const double brewster = std::atan(1.5);
  const double ci = std::cos(brewster), ct = std::sqrt(1 - std::pow(std::sin(brewster) / 1.5, 2));
  const double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
  EXPECT_NEAR(fresnel_dielectric(real(ci), 1, real(1.5)).reflect, 0.5 * rs * rs, 1e-6);
  // Total internal reflection beyond the critical angle asin(1 / 1.5) from inside.
  const double critical = std::asin(1 / 1.5);
  EXPECT_LT(fresnel_dielectric(real(std::cos(critical - 0.01)), real(1.5), 1).reflect, 1);
  const Fresnel tir = fresnel_dielectric(real(std::cos(critical + 0.01)), real(1.5), 1);
  EXPECT_EQ(tir.reflect, 1);
  EXPECT_EQ(tir.transmit, 0);
}

TEST(Fresnel, RefractionFollowsSnellsLaw) {
  const Vec3 n{0, 1, 0};
  for (real angle : {real(0.1), real(0.5), real(1.0), real(1.4)}) {
    const Vec3 d{std::sin(angle), -std::cos(angle), 0};
    const Fresnel f = fresnel_dielectric(-dot(d, n), 1, real(1.5));
    const Vec3 t = refract(d, n, 1, real(1.5), f.cos_t);
    EXPECT_NEAR(length(t), 1, 1e-6);
    EXPECT_NEAR(std::sin(angle), 1.5 * t.x, 1e-6);  // n1 sin(theta_i) = n2 sin(theta_t)
    EXPECT_NEAR(-t.y, f.cos_t, 1e-6);
    const Vec3 r = reflect(d, n);
    EXPECT_NEAR(r.x, d.x, 1e-7);
    EXPECT_NEAR(r.y, -d.y, 1e-7);
  }
}

}  // namespace
}  // namespace pd
