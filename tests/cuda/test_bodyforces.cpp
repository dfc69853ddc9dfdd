// Kernel 5 body: Levine eq. 7 projectile force, gravity, floor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "cuda/kernels/bodyforces.h"
#include "cuda/kernels/integrate.h"

namespace pd {
namespace {

TEST(BodyForces, ProjectilePeaksAtTheRadius) {
  const real r = real(0.02), ks = real(1e7);
  EXPECT_NEAR(projectile_magnitude(r, r, ks), ks * r * r, 1e-5 * ks * r * r);
  // The peak: no sampled distance exceeds the value at r.
  for (int k = 0; k <= 1000; ++k) {
    const real d = real(0.75) * r + real(0.75) * r * real(k) / real(1000);
    EXPECT_LE(projectile_magnitude(d, r, ks), ks * r * r * real(1 + 1e-5));
  }
}

TEST(BodyForces, ProjectileFormulaValue) {
  const double r = 0.02, ks = 3e6, d = 0.027;
  const double g = 16 * (d - 0.75 * r) * (d - 1.5 * r) * (d - 1.5 * r);
  EXPECT_NEAR(projectile_magnitude(real(d), real(r), real(ks)), ks * std::pow(g, 2.0 / 3.0),
              1e-5 * ks * r * r);
}

TEST(BodyForces, ProjectileZeroOutsideItsShell) {
  const real r = real(0.02), ks = real(1e7);
  EXPECT_EQ(projectile_magnitude(real(0.74) * r, r, ks), 0);
  EXPECT_EQ(projectile_magnitude(real(1.51) * r, r, ks), 0);
  EXPECT_EQ(projectile_magnitude(real(0), r, ks), 0);
  // Continuous at both ends of the shell.
  EXPECT_NEAR(projectile_magnitude(real(0.750001) * r, r, ks), 0, 1e-3 * ks * r * r);
  EXPECT_NEAR(projectile_magnitude(real(1.4999) * r, r, ks), 0, 1e-3 * ks * r * r);
}

TEST(BodyForces, ProjectileDirectionIsHalfwayBetweenMotionAndRepulsion) {
  Projectile pr;
  pr.center0 = {0, 0, 0};
  pr.velocity = {0, real(-10), 0};
  pr.radius = real(1);
  pr.strength = real(1);
  const Vec3 f = projectile_force({real(1), 0, 0}, pr, 0);  // repulsion +x, motion -y
  EXPECT_NEAR(f.x, -f.y, 1e-6);
  EXPECT_GT(f.x, 0);
  EXPECT_NEAR(length(f), 1.0, 1e-5);
  // The centre moves with the projectile velocity.
  const Vec3 later = projectile_force({real(1), real(-0.5), 0}, pr, real(0.05));
  EXPECT_NEAR(later.x, f.x, 1e-5);
}

// One particle's records and a view of them.
struct OneParticle {
  Vec4 rest{0, 0, 0, 1}, disp{0, 0, 0, 1};
  Vec3 vel{0, 0, 0}, force{0, 0, 0};
  real inv_mass = 1;
  uint8_t flags = 0;
  Ledger ledger;
  ParticlesView view() {
    ParticlesView p;
    p.n = 1;
    p.rest = {&rest, 1};
    p.disp = {&disp, 1};
    p.vel = {&vel, 1};
    p.force = {&force, 1};
    p.inv_mass = {&inv_mass, 1};
    p.flags = {&flags, 1};
    p.ledger = {&ledger, 1};
    return p;
  }
};

TEST(BodyForces, GravityAndFloorReflection) {
  OneParticle one;
  one.rest = {0, real(-0.001), 0, 1};
  one.vel = {0, real(-2), 0};
  one.force = {real(1), 0, 0};
  one.inv_mass = real(0.5);
  const ParticlesView p = one.view();
  Vec3& force = one.force;
  Vec3& vel = one.vel;
  Ledger& ledger = one.ledger;
  StepParams sp;
  sp.gravity = {0, real(-9.81), 0};
  sp.floor_enabled = 1;
  sp.floor_height = 0;
  sp.restitution = real(0.99);
  body_forces(0, p, sp);
  EXPECT_FLOAT_EQ(force.x, 1);
  EXPECT_FLOAT_EQ(force.y, real(2 * -9.81));
  // The floor reflects the full-step velocity in the velocity update and books the loss.
  force = {0, 0, 0};
  sp.dt = real(1e-6);
  velocity_update(0, p, sp);
  EXPECT_FLOAT_EQ(vel.y, real(1.98));
  EXPECT_NEAR(ledger.work, -0.5 * 2.0 * 4.0 * (1 - 0.99 * 0.99), 1e-6);
  // Moving up already: not reflected again.
  velocity_update(0, p, sp);
  EXPECT_FLOAT_EQ(vel.y, real(1.98));
}

// Gravity alone: the instantiation without pushers reads no position and gives the same bits.
TEST(BodyForces, GravityAloneMatchesTheFullKernelBitForBit) {
  OneParticle one;
  one.rest = {real(0.3), real(-0.7), real(0.1), 1};
  one.disp = {real(1e-4), 0, real(-2e-5), 1};
  one.vel = {0, real(-2), 0};
  one.inv_mass = real(0.37);
  const Vec3 start{real(1.25), real(-3.5e-3), real(7.1)};
  Vec3& force = one.force;
  force = start;
  const ParticlesView p = one.view();
  StepParams sp;
  sp.gravity = {real(0.1), real(-9.81), 0};
  body_forces<true>(0, p, sp);
  const Vec3 full = force;
  force = start;
  body_forces<false>(0, p, sp);
  EXPECT_EQ(std::memcmp(&full, &force, sizeof(Vec3)), 0);
  EXPECT_FLOAT_EQ(force.y, start.y + real(-9.81) / one.inv_mass);
}

// The floor test with a bound on the reference positions gives the test on the position, and
// reads no reference position where the displacement keeps the particle above the floor.
TEST(BodyForces, FloorTestReadsTheRestPositionOnlyWhereTheDisplacementCouldReachTheFloor) {
  OneParticle one;
  const ParticlesView p = one.view();
  StepParams sp;
  sp.floor_enabled = 1;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform;
  int below = 0, above = 0;
  for (int k = 0; k < 20000; ++k) {
    const real y = real(normal(rng) * 0.1), u = real(normal(rng) * 1e-2);
    one.rest = {0, y, 0, 1};
    one.disp = {0, u, 0, 1};
    // Floors at, just beside and around the position, and bounds at the rest position or below.
    const real at = y + u;
    const real floors[] = {at, std::nextafter(at, real(1)), std::nextafter(at, real(-1)),
                           real(normal(rng) * 0.1)};
    sp.floor_height = floors[k % 4];
    sp.lowest_rest_y = k % 3 == 0 ? y : y - real(uniform(rng) * 0.05);
    const bool expected = p.position(0).y < sp.floor_height;
    EXPECT_EQ(below_floor(0, p, sp), expected) << k;
    sp.lowest_rest_y = -INFINITY;
    EXPECT_EQ(below_floor(0, p, sp), expected) << k;
    (expected ? below : above) += 1;
  }
  EXPECT_GT(below, 1000);
  EXPECT_GT(above, 1000);
  // Above the floor from the bound: the reference position is not read (a NaN there is not seen).
  one.rest = {0, real(NAN), 0, 1};
  one.disp = {0, real(0.5), 0, 1};
  sp.floor_height = 0;
  sp.lowest_rest_y = real(-0.25);
  EXPECT_FALSE(below_floor(0, p, sp));
  one.disp = {0, real(0.1), 0, 1};  // within the bound's reach: read (NaN is not below)
  EXPECT_FALSE(below_floor(0, p, sp));
  one.rest = {0, real(-0.2), 0, 1};
  EXPECT_TRUE(below_floor(0, p, sp));
}

}  // namespace
}  // namespace pd
