// Rigid colliders (cuda/kernels/colliders.h): each shape's signed distance and normal, the
// contact law, and runs on the CPU reference against analytic answers: a particle resting on a
// plane, one sliding to a stop under friction, an undamped bounce, and a moving sphere.
#include "cuda/kernels/colliders.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>

#include "cuda/engine/engine.h"
#include "cuda/engine/motion.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kG = 9.81;

// The runs here step a few particles many thousand times: one OpenMP thread, so that the time is
// the physics' and not the threads' meeting at every loop (slow where the cores are shared).
class OneThread {
 public:
  OneThread() : before_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~OneThread() { omp_set_num_threads(before_); }

 private:
  int before_;
};

Collider shape(ColliderShape kind, Vec3 size) {
  Collider c;
  c.shape = kind;
  c.size = size;
  return c;
}

void expect_surface(const Collider& c, Vec3 x, double distance, Vec3 normal) {
  const SurfacePoint s = collider_surface(c, x);
  EXPECT_NEAR(s.distance, distance, 1e-6) << x.x << " " << x.y << " " << x.z;
  EXPECT_NEAR(s.normal.x, normal.x, 1e-6);
  EXPECT_NEAR(s.normal.y, normal.y, 1e-6);
  EXPECT_NEAR(s.normal.z, normal.z, 1e-6);
}

TEST(Colliders, EachShapeGivesItsSignedDistanceAndNormal) {
  expect_surface(shape(kColliderPlane, {}), {3, real(0.25), -2}, 0.25, {0, 1, 0});
  expect_surface(shape(kColliderPlane, {}), {0, real(-0.5), 0}, -0.5, {0, 1, 0});
  expect_surface(shape(kColliderSphere, {1, 0, 0}), {0, 0, 3}, 2, {0, 0, 1});
  expect_surface(shape(kColliderSphere, {1, 0, 0}), {real(0.5), 0, 0}, -0.5, {1, 0, 0});
  const Collider box = shape(kColliderBox, {1, 2, 3});
  expect_surface(box, {3, 0, 0}, 2, {1, 0, 0});                  // off a face
  expect_surface(box, {4, 6, 0}, 5, {real(0.6), real(0.8), 0});  // off an edge
  expect_surface(box, {0, real(-1.5), 0}, -0.5, {0, -1, 0});     // inside, nearest face below
  const Collider capsule = shape(kColliderCapsule, {real(0.5), 2, 0});
  expect_surface(capsule, {2, 1, 0}, 1.5, {1, 0, 0});  // beside the segment
  expect_surface(capsule, {0, 4, 0}, 1.5, {0, 1, 0});  // past its end
  const Collider cylinder = shape(kColliderCylinder, {1, 2, 0});
  expect_surface(cylinder, {0, 3, 0}, 1, {0, 1, 0});                  // above the flat end
  expect_surface(cylinder, {0, 0, 3}, 2, {0, 0, 1});                  // beside it
  expect_surface(cylinder, {4, 6, 0}, 5, {real(0.6), real(0.8), 0});  // past the rim
  expect_surface(cylinder, {real(0.5), real(1.8), 0}, -0.2, {0, 1, 0});
}

TEST(Colliders, PoseTurnsAndMovesTheShape) {
  // A plane whose normal turns from +y towards +x at 90 degrees per second, moving up at 1 m/s.
  MotionScript motion;
  ColliderScript script;
  script.velocity = {0, 1, 0};
  script.omega = {0, 0, -M_PI / 2};
  motion.colliders.push_back(script);
  std::vector<Collider> c(1);
  motion.pose_colliders(1.0, c);
  EXPECT_NEAR(c[0].center.y, 1, 1e-6);
  expect_surface(c[0], {2, 1, 0}, 2, {1, 0, 0});
}

TEST(Colliders, ContactLawPushesDampsAndRubs) {
  Collider c = shape(kColliderPlane, {});
  c.stiffness = real(1e6);
  const real volume = real(1e-6), mass = real(2e-3), dt = real(1e-5);  // a 1 cm particle
  // 1 mm into the plane's skin (the particle's radius is 5 mm), at rest: K V^(1/3) d upward.
  Vec3 f = collider_force(c, {0, real(0.004), 0}, {0, 0, 0}, volume, mass, dt);
  EXPECT_NEAR(f.y, 1e6 * 0.01 * 0.001, 1e-3);
  EXPECT_EQ(f.x, 0);
  // Out of reach: nothing.
  f = collider_force(c, {0, real(0.006), 0}, {0, 0, 0}, volume, mass, dt);
  EXPECT_EQ(f.y, 0);
  // Damped: approaching pushes harder, separating less; never a pull.
  c.damping = real(0.5);
  const double k = 1e6 * 0.01, damper = 2 * 0.5 * std::sqrt(k * 2e-3);
  f = collider_force(c, {0, real(0.004), 0}, {0, real(-0.1), 0}, volume, mass, dt);
  EXPECT_NEAR(f.y, k * 0.001 + damper * 0.1, 1e-3);
  f = collider_force(c, {0, real(0.004), 0}, {0, real(100), 0}, volume, mass, dt);
  EXPECT_EQ(f.y, 0);
  // Friction: a slow slide stops within the step (static); a fast one feels mu_d times the push.
  c.damping = 0;
  c.friction_static = real(0.6);
  c.friction_dynamic = real(0.4);
  const double push = k * 0.001;  // 10 N
  f = collider_force(c, {0, real(0.004), 0}, {real(1e-3), 0, 0}, volume, mass, dt);
  EXPECT_NEAR(f.x, -2e-3 * 1e-3 / 1e-5, 1e-4);  // m v / dt = 0.2 N <= 0.6 x 10 N
  f = collider_force(c, {0, real(0.004), 0}, {real(10), 0, 0}, volume, mass, dt);
  EXPECT_NEAR(f.x, -0.4 * push, 1e-4);
  // The surface's own motion counts: a plane moving with the particle does not rub.
  c.velocity = {real(10), 0, 0};
  f = collider_force(c, {0, real(0.004), 0}, {real(10), 0, 0}, volume, mass, dt);
  EXPECT_EQ(f.x, 0);
}

TEST(Colliders, LammpsIndentLawIsKTimesTheDepthSquaredPerVolume) {
  // LAMMPS fix indent, sphere of radius R: K (R - r)^2 on a point at distance r < R, radial; on a
  // peridynamic atom (atom_style peri) a force density, so K (R - r)^2 V on the particle.
  Collider c = shape(kColliderSphere, {real(5e-4), 0, 0});
  c.law = kLawLammpsIndent;
  c.stiffness = real(1e17);  // examples/peri's K
  const real volume = real(1e-12), mass = real(2e-9), dt = real(1e-8);
  const Vec3 f = collider_force(c, {0, 0, real(4e-4)}, {0, 0, -1}, volume, mass, dt);
  EXPECT_NEAR(f.z, 1e17 * 1e-4 * 1e-4 * 1e-12, 1e-3 * 1e-3);
  EXPECT_EQ(f.x, 0);
  // Only points inside count (no particle radius), and there is no damping or friction.
  EXPECT_EQ(collider_force(c, {0, 0, real(5.1e-4)}, {0, 0, 0}, volume, mass, dt).z, 0);
  c.friction_dynamic = real(1);
  const Vec3 g = collider_force(c, {0, 0, real(4e-4)}, {real(1), 0, 0}, volume, mass, dt);
  EXPECT_EQ(g.x, 0);
  EXPECT_NEAR(g.z, f.z, 1e-6 * f.z);
}

// One particle of side h (no bonds) above a plane collider at y = 0, under gravity.
SimulationInput particle_on_plane(double h, double height, Vec3 velocity, Collider plane) {
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = testing::glass_material(h);
  const double volume = h * h * h;
  in.particles.add({0, real(height), 0}, velocity, real(volume), real(2440 * volume), real(1e-3), 0, 0);
  in.step.gravity = {0, real(-kG), 0};
  in.colliders.push_back(plane);
  in.motion.colliders.push_back({});
  return in;
}

ParticleState run(SimulationInput in, double dt, int64_t steps) {
  const OneThread one;
  in.step.dt = real(dt);
  auto engine = make_cpu_engine(in);
  engine->advance(steps);
  ParticleState s;
  engine->read_state(s);
  return s;
}

TEST(Colliders, ParticleComesToRestOnAPlaneAtItsStaticPenetration) {
  const double h = 0.01, stiffness = 1e6;
  Collider plane = shape(kColliderPlane, {});
  plane.stiffness = real(stiffness);
  plane.damping = real(0.5);
  const SimulationInput in = particle_on_plane(h, 0.02, {0, 0, 0}, plane);
  // Rest: K h d = m g, the centre at h/2 - d.
  const double mass = 2440 * h * h * h, depth = mass * kG / (stiffness * h);
  const double period = 2 * M_PI * std::sqrt(mass / (stiffness * h));
  const ParticleState s = run(in, period / 50, 20000);
  EXPECT_NEAR(0.02 + s.disp[0].y, 0.5 * h - depth, 1e-2 * depth);
  EXPECT_NEAR(s.vel[0].y, 0, 2 * M_PI / period * 1e-2 * depth);  // what 1% of the depth would swing
}

TEST(Colliders, SlidingParticleStopsWhereFrictionSays) {
  // Launched along x at v0 on the plane (resting on it from the start); mu_d = 0.3 stops it after
  // v0^2 / (2 mu_d g).
  const double h = 0.01, v0 = 0.5, mu = 0.3;
  Collider plane = shape(kColliderPlane, {});
  plane.stiffness = real(1e6);
  plane.damping = real(1);
  plane.friction_dynamic = real(mu);
  plane.friction_static = real(mu);
  const double mass = 2440 * h * h * h, depth = mass * kG / (1e6 * h);
  const SimulationInput in = particle_on_plane(h, 0.5 * h - depth, {real(v0), 0, 0}, plane);
  const double dt = 1e-5;
  const double stop_time = v0 / (mu * kG);
  const ParticleState s = run(in, dt, int64_t(1.5 * stop_time / dt));
  const double expected = v0 * v0 / (2 * mu * kG);
  EXPECT_NEAR(s.disp[0].x, expected, 0.01 * expected);
  EXPECT_NEAR(s.vel[0].x, 0, 1e-4);
}

TEST(Colliders, UndampedBounceKeepsItsHeight) {
  // Dropped from 2 cm onto a stiff plane with no damping: it comes back up to within 1% of the
  // fall (energy kept by the penalty spring and the symplectic step).
  const double h = 0.01, drop = 0.02;
  Collider plane = shape(kColliderPlane, {});
  plane.stiffness = real(1e7);
  const SimulationInput in = particle_on_plane(h, drop, {0, 0, 0}, plane);
  const double dt = 4e-6, fall = std::sqrt(2 * (drop - 0.5 * h) / kG);
  // After one fall, the contact and the rise: at the top again.
  const ParticleState s = run(in, dt, int64_t(2 * fall / dt));
  EXPECT_NEAR(drop + s.disp[0].y, drop, 0.01 * (drop - 0.5 * h));
}

TEST(Colliders, MovingSpherePushesABlockAlong) {
  const OneThread one;
  // A sphere sweeping through the side of a block at 1 m/s (no gravity): the block is pushed in
  // the sphere's direction, and the ledger records the sphere's work.
  SimulationInput in = testing::lattice_block(6, 6, 6, 1e-3);
  Collider sphere = shape(kColliderSphere, {real(2e-3), 0, 0});
  sphere.stiffness = real(1e10);
  in.colliders.push_back(sphere);
  ColliderScript script;
  script.center = {-2.3e-3, 2.5e-3, 2.5e-3};  // 0.09 mm into the reach of the nearest particles
  script.velocity = {1, 0, 0};
  in.motion.colliders.push_back(script);
  in.step.dt = real(2e-8);
  auto engine = make_cpu_engine(in);
  engine->advance(1000);
  ParticleState s;
  engine->read_state(s);
  const std::array<double, 3> p = testing::total_momentum(in, s.vel);
  EXPECT_GT(p[0], 0);
  EXPECT_NEAR(p[1], 0, 1e-3 * p[0]);
  EXPECT_NEAR(p[2], 0, 1e-3 * p[0]);
  EXPECT_GT(engine->energy().work, 0);
}

// A free sphere of mass `mass` at `x0` moving at `v0`, and a 6^3 glass block at rest, no gravity.
SimulationInput ball_and_block(double mass, double damping, Vec3 x0, Vec3 v0) {
  SimulationInput in = testing::lattice_block(6, 6, 6, 1e-3);
  Collider sphere = shape(kColliderSphere, {real(2e-3), 0, 0});
  sphere.stiffness = real(1e10);
  sphere.damping = real(damping);
  in.colliders.push_back(sphere);
  ColliderScript script;
  script.center = {x0.x, x0.y, x0.z};
  script.velocity = {v0.x, v0.y, v0.z};
  script.mass = mass;
  const double i = 0.4 * mass * 4e-6;
  script.inertia = {i, i, i};
  in.motion.colliders.push_back(script);
  in.step.dt = real(2e-8);
  return in;
}

// Momentum of the particles plus the free colliders' (masses given).
std::array<double, 3> total_momentum(Engine& engine, const SimulationInput& in,
                                     const std::vector<double>& masses) {
  ParticleState s;
  engine.read_state(s);
  std::array<double, 3> p = testing::total_momentum(in, s.vel);
  const std::vector<Collider> c = engine.colliders();
  for (size_t k = 0; k < masses.size(); ++k) {
    p[0] += masses[k] * double(c[k].velocity.x);
    p[1] += masses[k] * double(c[k].velocity.y);
    p[2] += masses[k] * double(c[k].velocity.z);
  }
  return p;
}

TEST(Colliders, FreeSphereFallsFreely) {
  const OneThread one;
  SimulationInput in = ball_and_block(1e-3, 0, {0, real(0.1), 0}, {real(0.5), 0, 0});
  in.step.gravity = {0, real(-kG), 0};
  in.step.dt = real(1e-5);
  auto engine = make_cpu_engine(in);
  engine->advance(1000);  // 10 ms, far from the block
  const Collider c = engine->colliders()[0];
  EXPECT_NEAR(c.velocity.x, 0.5, 1e-6);
  EXPECT_NEAR(c.velocity.y, -kG * 0.01, 1e-5);
  EXPECT_NEAR(c.center.x, 0.005, 1e-6);
  EXPECT_NEAR(c.center.y, 0.1 - 0.5 * kG * 1e-4, 1e-6);
}

// A 0.1 g sphere at 2 m/s into the side of the block (0.5 g), run 0.3 ms (the contact lasts a
// few microseconds): the momentum of sphere plus particles, and the energy left in the sphere's
// and the block's motion and the block's strain.
struct Hit {
  std::array<double, 3> momentum;
  double energy, ball_speed;
};
constexpr double kBallMass = 1e-4, kBallSpeed = 2;

Hit hit_the_block(double damping) {
  const OneThread one;
  const SimulationInput in = ball_and_block(kBallMass, damping, {real(-2.6e-3), real(2.5e-3), real(2.5e-3)},
                                            {real(kBallSpeed), 0, 0});
  auto engine = make_cpu_engine(in);
  engine->advance(15000);
  const Collider c = engine->colliders()[0];
  const double v2 =
      double(c.velocity.x * c.velocity.x + c.velocity.y * c.velocity.y + c.velocity.z * c.velocity.z);
  const Energy e = engine->energy();
  return {total_momentum(*engine, in, {kBallMass}), 0.5 * kBallMass * v2 + e.kinetic + e.strain,
          std::sqrt(v2)};
}

TEST(Colliders, FreeSphereAndBlockKeepTheirMomentumAndEnergyInAnElasticHit) {
  // Undamped: momentum kept to round-off; the sphere has slowed; the energy is what it brought,
  // within 2%.
  const Hit h = hit_the_block(0);
  const double p0 = kBallMass * kBallSpeed, e0 = 0.5 * kBallMass * kBallSpeed * kBallSpeed;
  EXPECT_NEAR(h.momentum[0], p0, 1e-4 * p0);
  EXPECT_NEAR(h.momentum[1], 0, 1e-4 * p0);
  EXPECT_NEAR(h.momentum[2], 0, 1e-4 * p0);
  EXPECT_LT(h.ball_speed, 0.9 * kBallSpeed);
  EXPECT_NEAR(h.energy, e0, 0.02 * e0);
}

TEST(Colliders, DampedHitLosesEnergyButKeepsMomentum) {
  const Hit h = hit_the_block(1);
  const double p0 = kBallMass * kBallSpeed, e0 = 0.5 * kBallMass * kBallSpeed * kBallSpeed;
  EXPECT_NEAR(h.momentum[0], p0, 1e-4 * p0);
  EXPECT_LT(h.energy, 0.95 * e0);
}

}  // namespace
}  // namespace pd
