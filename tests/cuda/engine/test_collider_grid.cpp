// The colliders' grid (cuda/engine/collider_grid.h): a particle's force from the colliders of its
// cell and the planes equals the sum over every collider, for 64 colliders of every shape scattered
// around particles of two sizes; and the grid's lists are what ColliderGridView says.
#include "cuda/engine/collider_grid.h"

#include <gtest/gtest.h>

#include <random>

#include "cuda/kernels/colliders.h"

namespace pd {
namespace {

TEST(ColliderGrid, CellsGiveTheForceOfEveryCollider) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1), s(0.02, 0.15);
  std::vector<Collider> colliders;
  for (int k = 0; k < 64; ++k) {
    Collider c;
    c.shape = uint8_t(1 + k % 4);  // sphere, box, capsule, cylinder
    c.size = {real(s(rng)), real(s(rng)), real(s(rng))};
    c.center = {real(u(rng)), real(u(rng)), real(u(rng))};
    c.stiffness = real(1e9);
    const double x = c.size.x, y = c.size.y, z = c.size.z;
    c.bound = real(c.shape == kColliderSphere    ? x
                   : c.shape == kColliderBox     ? std::sqrt(x * x + y * y + z * z)
                   : c.shape == kColliderCapsule ? x + y
                                                 : std::sqrt(x * x + y * y));
    colliders.push_back(c);
  }
  Collider plane;  // unbounded, always read
  plane.center = {0, real(-0.9), 0};
  plane.stiffness = real(1e9);
  colliders.push_back(plane);
  const real largest = real(0.04);
  std::vector<int32_t> lists;
  ColliderGridView g = ColliderGrid::build(colliders, largest, lists);
  EXPECT_GT(g.dims, 1);
  EXPECT_EQ(lists.size() - size_t(g.unbounded), 1u);  // the plane
  g.lists = {lists.data(), int64_t(lists.size())};
  std::vector<Vec4> spheres;
  for (const Collider& c : colliders) spheres.push_back(with_w(c.center, c.bound > 0 ? c.bound : real(-1)));
  StepParams sp;
  sp.dt = real(1e-6);
  sp.colliders = {colliders.data(), int64_t(colliders.size())};
  sp.collider_spheres = {spheres.data(), int64_t(spheres.size())};
  sp.collider_grid = g;
  // Particles of side 2 cm and 4 cm at random, one at a time through a one-particle view.
  int touched = 0;
  for (int n = 0; n < 4000; ++n) {
    const real side = n % 2 ? real(0.02) : largest, volume = side * side * side;
    Vec4 disp{0, 0, 0, 0};
    const Vec3 x{real(u(rng)), real(u(rng)), real(u(rng))};
    const Vec4 rest = with_w(x, volume);
    Vec3 vel{real(u(rng)), 0, 0};
    const real inv_mass = real(1) / (1000 * volume);
    ParticlesView p;
    p.n = 1;
    p.rest = {&rest, 1};
    p.disp = {&disp, 1};
    p.vel = {&vel, 1};
    p.inv_mass = {&inv_mass, 1};
    const Vec3 f = colliders_force(0, p, sp);
    Vec3 expected{0, 0, 0};
    for (const Collider& c : colliders) expected += collider_force(c, x, vel, volume, 1000 * volume, sp.dt);
    touched += length(expected) > 0;
    EXPECT_NEAR(f.x, expected.x, 1e-5 * (1 + std::abs(double(expected.x))));
    EXPECT_NEAR(f.y, expected.y, 1e-5 * (1 + std::abs(double(expected.y))));
    EXPECT_NEAR(f.z, expected.z, 1e-5 * (1 + std::abs(double(expected.z))));
  }
  EXPECT_GT(touched, 200);  // the check saw forces, not only empty cells
}

}  // namespace
}  // namespace pd
