// Contact between rigid colliders (cuda/engine/body_contact.h), on the CPU reference: each shape's
// probe points, a ball dropped on the ground coming to rest, a box sliding to the stop friction
// gives, a head-on hit of equal masses trading their velocities, and a ball knocking a standing
// box over.
#include "cuda/engine/body_contact.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>

#include "cuda/engine/engine.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kG = 9.81;

class OneThread {  // thousands of steps of one particle: the threads' meeting would be the time
 public:
  OneThread() : before_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~OneThread() { omp_set_num_threads(before_); }

 private:
  int before_;
};

Collider shape(ColliderShape kind, Vec3 size, double stiffness, double damping, double friction) {
  Collider c;
  c.shape = kind;
  c.size = size;
  c.stiffness = real(stiffness);
  c.damping = real(damping);
  c.friction_static = c.friction_dynamic = real(friction);
  return c;
}

// A scene of colliders alone (one glass particle far away, as the engine needs particles).
struct Bodies {
  SimulationInput in;
  std::vector<double> masses;

  explicit Bodies(double gravity) {
    in.materials.count = 1;
    in.materials.m[0] = testing::glass_material(0.01);
    in.particles.add({100, 0, 0}, {0, 0, 0}, real(1e-6), real(2.44e-3), real(1e-3), 0, 0);
    in.step.gravity = {0, real(-gravity), 0};
  }
  // Adds a collider, free where `mass` > 0 (with principal moments `inertia`).
  void add(const Collider& c, std::array<double, 3> center, std::array<double, 3> velocity, double mass,
           std::array<double, 3> inertia = {0, 0, 0}) {
    in.colliders.push_back(c);
    ColliderScript s;
    s.center = center;
    s.velocity = velocity;
    s.mass = mass;
    s.inertia = inertia;
    in.motion.colliders.push_back(s);
    masses.push_back(mass);
  }
  std::vector<Collider> run(double dt, double seconds) {
    const OneThread one;
    in.step.dt = real(dt);
    auto engine = make_cpu_engine(in);
    engine->advance(int64_t(std::llround(seconds / dt)));
    return engine->colliders();
  }
};

std::array<double, 3> box_inertia(double m, Vec3 h) {
  const double x = double(h.x) * double(h.x), y = double(h.y) * double(h.y), z = double(h.z) * double(h.z);
  return {m / 3 * (y + z), m / 3 * (x + z), m / 3 * (x + y)};
}

TEST(BodyContact, ShapesGiveTheirProbePoints) {
  EXPECT_EQ(shape_probes(shape(kColliderSphere, {1, 0, 0}, 1, 0, 0)).size(), 1u);
  EXPECT_EQ(shape_probes(shape(kColliderCapsule, {1, 2, 0}, 1, 0, 0)).size(), 5u);
  EXPECT_EQ(shape_probes(shape(kColliderPlane, {}, 1, 0, 0)).size(), 0u);
  const std::vector<Probe> box = shape_probes(shape(kColliderBox, {1, 2, 3}, 1, 0, 0));
  EXPECT_EQ(box.size(), 20u);  // 8 corners, 12 edge midpoints, all on the surface
  for (const Probe& p : box) EXPECT_NEAR(box_surface(p.point, {1, 2, 3}).distance, 0, 1e-6);
  const std::vector<Probe> cylinder = shape_probes(shape(kColliderCylinder, {1, 2, 0}, 1, 0, 0));
  EXPECT_EQ(cylinder.size(), 48u);
  for (const Probe& p : cylinder) EXPECT_NEAR(cylinder_surface(p.point, 1, 2).distance, 0, 1e-6);
}

TEST(BodyContact, TwoFixedCollidersExertNothing) {
  const std::vector<Collider> c = {shape(kColliderPlane, {}, 1e8, 0, 0),
                                   shape(kColliderSphere, {1, 0, 0}, 1e8, 0, 0)};
  const std::vector<Wrench> w = body_contact_wrenches(c, {0, 0}, 1e-4);  // the sphere deep in the plane
  EXPECT_EQ(w[1].fy, 0);
}

TEST(BodyContact, BallDroppedOnAPlaneComesToRest) {
  // A 5 cm steel ball dropped 15 cm onto damped ground: it bounces lower each time and rests with
  // its centre at r - m g / k, k = K r.
  Bodies b(kG);
  b.add(shape(kColliderPlane, {}, 1e8, 0.3, 0.5), {0, 0, 0}, {0, 0, 0}, 0);
  const double r = 0.05, mass = 7800 * 4.0 / 3.0 * M_PI * r * r * r;
  b.add(shape(kColliderSphere, {real(r), 0, 0}, 1e8, 0.3, 0.5), {0, 0.2, 0}, {0, 0, 0}, mass,
        {0.4 * mass * r * r, 0.4 * mass * r * r, 0.4 * mass * r * r});
  const std::vector<Collider> c = b.run(1e-4, 1.0);
  const double depth = mass * kG / (1e8 * r);
  EXPECT_NEAR(c[1].center.y, r - depth, 0.01 * depth);
  EXPECT_NEAR(c[1].velocity.y, 0, 1e-6);
  EXPECT_NEAR(c[1].center.x, 0, 1e-9);
}

TEST(BodyContact, SlidingBoxStopsWhereFrictionSays) {
  // A 10 cm cube of 1 kg launched at 1 m/s along the ground, mu = 0.3: it stops after
  // v0^2 / (2 mu g) and stays.
  Bodies b(kG);
  const double mu = 0.3, v0 = 1, stiffness = 1e8;
  b.add(shape(kColliderPlane, {}, stiffness, 1, mu), {0, 0, 0}, {0, 0, 0}, 0);
  const Vec3 h{real(0.05), real(0.05), real(0.05)};
  const double k = stiffness * 0.05 * 8;  // 4 corners and 4 edge midpoints on the ground
  b.add(shape(kColliderBox, h, stiffness, 1, mu), {0, 0.05 - kG / k, 0}, {v0, 0, 0}, 1, box_inertia(1, h));
  const std::vector<Collider> c = b.run(2e-5, 1.5 * v0 / (mu * kG));
  const double expected = v0 * v0 / (2 * mu * kG);
  EXPECT_NEAR(c[1].center.x, expected, 0.01 * expected);
  EXPECT_NEAR(c[1].velocity.x, 0, 1e-4);
  EXPECT_NEAR(c[1].center.y, 0.05, 1e-4);  // still flat on the ground
}

TEST(BodyContact, EqualMassesTradeVelocitiesHeadOnAndKeepMomentum) {
  // No gravity: a 1 kg ball at 2 m/s into the face of a resting 1 kg box, undamped: the ball stops
  // and the box leaves at 2 m/s; the momentum of the two is kept to round-off.
  Bodies b(0);
  const double r = 0.05;
  const Vec3 h{real(0.05), real(0.05), real(0.05)};
  b.add(shape(kColliderSphere, {real(r), 0, 0}, 1e8, 0, 0), {-0.11, 0, 0}, {2, 0, 0}, 1,
        {0.4 * r * r, 0.4 * r * r, 0.4 * r * r});
  b.add(shape(kColliderBox, h, 1e8, 0, 0), {0, 0, 0}, {0, 0, 0}, 1, box_inertia(1, h));
  const std::vector<Collider> c = b.run(1e-5, 0.05);
  EXPECT_NEAR(c[0].velocity.x, 0, 0.01 * 2);
  EXPECT_NEAR(c[1].velocity.x, 2, 0.01 * 2);
  EXPECT_NEAR(double(c[0].velocity.x) + double(c[1].velocity.x), 2, 1e-5);
}

TEST(BodyContact, ObliqueDampedHitWithFrictionKeepsMomentum) {
  // Off-centre, damped and rubbing: energy goes, momentum stays (float poses: to 1e-5).
  Bodies b(0);
  const Vec3 h{real(0.05), real(0.1), real(0.05)};
  b.add(shape(kColliderSphere, {real(0.05), 0, 0}, 1e8, 0.5, 0.4), {-0.11, 0.06, 0.01}, {2, 0.3, -0.2}, 2,
        {0.002, 0.002, 0.002});
  b.add(shape(kColliderBox, h, 1e8, 0.5, 0.4), {0, 0, 0}, {0, 0, 0}, 1, box_inertia(1, h));
  const std::vector<Collider> c = b.run(1e-5, 0.05);
  const double px = 2 * double(c[0].velocity.x) + double(c[1].velocity.x);
  const double py = 2 * double(c[0].velocity.y) + double(c[1].velocity.y);
  const double pz = 2 * double(c[0].velocity.z) + double(c[1].velocity.z);
  EXPECT_NEAR(px, 4, 1e-5);
  EXPECT_NEAR(py, 0.6, 1e-5);
  EXPECT_NEAR(pz, -0.4, 1e-5);
  EXPECT_GT(double(c[1].velocity.x), 0.5);  // the box was hit
  const double w2 = double(dot(c[1].omega, c[1].omega));
  EXPECT_GT(w2, 0);  // and turned by the off-centre push
}

TEST(BodyContact, BallKnocksAStandingBoxOver) {
  // A 40 cm tall 1 kg box standing on frictional ground, hit near its top by a 2 kg ball at
  // 3 m/s: it tips over and lies on its side.
  Bodies b(kG);
  b.add(shape(kColliderPlane, {}, 1e8, 0.5, 0.6), {0, 0, 0}, {0, 0, 0}, 0);
  const Vec3 h{real(0.05), real(0.2), real(0.05)};
  b.add(shape(kColliderBox, h, 1e8, 0.5, 0.6), {0, 0.2, 0}, {0, 0, 0}, 1, box_inertia(1, h));
  const double r = 0.05;
  b.add(shape(kColliderSphere, {real(r), 0, 0}, 1e8, 0.5, 0.6), {-0.11, 0.35, 0}, {3, 0, 0}, 2,
        {0.8 * r * r, 0.8 * r * r, 0.8 * r * r});
  const std::vector<Collider> c = b.run(2e-5, 1.0);
  const double up = double(c[1].rotation[4]);  // the world y of the box's long axis
  EXPECT_LT(std::abs(up), 0.05);               // lying
  EXPECT_NEAR(c[1].center.y, 0.05, 2e-3);      // on a long side
}

}  // namespace
}  // namespace pd
