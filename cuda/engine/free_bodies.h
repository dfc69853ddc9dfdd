// Free rigid colliders: bodies with mass and inertia that the particles push back (their
// reaction, reduced on the backend after `bodyforces`), the other colliders touch (body_contact.h)
// and gravity pulls. Integrated on the host by the velocity Verlet scheme the particles use: a half
// kick with the last reaction, a drift of the pose, the forces at the new state, a half kick with
// the new reaction. Each reaction is the exact sum of the forces the body put on the particles (and
// a body contact's force on one is minus that on the other), so the momentum of bodies and
// particles together is kept to round-off.
#pragma once

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/engine/body_contact.h"
#include "cuda/engine/motion.h"
#include "cuda/kernels/colliders.h"

namespace pd {

class FreeBodies {
 public:
  FreeBodies() = default;
  explicit FreeBodies(const std::vector<ColliderScript>& scripts) {
    for (size_t k = 0; k < scripts.size(); ++k) {
      const ColliderScript& s = scripts[k];
      masses_.push_back(s.free() ? s.mass : 0.0);
      if (!s.free()) continue;
      Body b;
      b.collider = int64_t(k);
      b.mass = s.mass;
      b.inertia = s.inertia;
      b.center = s.center;
      b.velocity = s.velocity;
      b.rotation = s.rotation;
      b.momentum = world_inertia_times(b, s.omega);
      bodies_.push_back(b);
    }
  }

  bool empty() const { return bodies_.empty(); }

  // Writes each body's pose and velocities into its collider.
  void pose(std::vector<Collider>& colliders) const {
    for (const Body& b : bodies_) {
      Collider& c = colliders[size_t(b.collider)];
      c.center = to_real(b.center);
      c.velocity = to_real(b.velocity);
      c.omega = to_real(angular_velocity(b));
      for (int q = 0; q < 9; ++q) c.rotation[q] = real(b.rotation[size_t(q)]);
    }
  }

  // The bodies' collider indices, in the order of reactions() and set_reactions().
  std::vector<int32_t> colliders() const {
    std::vector<int32_t> out;
    for (const Body& b : bodies_) out.push_back(int32_t(b.collider));
    return out;
  }

  // Adds the contacts between colliders (body_contact.h), at their pose in `posed`, to the
  // reactions.
  void touch(const std::vector<Collider>& posed, double dt, const MeshShapes& meshes) {
    const std::vector<Wrench> contact = body_contact_wrenches(posed, masses_, dt, meshes);
    for (Body& b : bodies_) b.reaction = b.reaction + contact[size_t(b.collider)];
  }

  // Each body's reaction, and setting them (a partitioned run's sum over the ranks).
  std::vector<Wrench> reactions() const {
    std::vector<Wrench> out;
    for (const Body& b : bodies_) out.push_back(b.reaction);
    return out;
  }
  void set_reactions(const std::vector<Wrench>& r) {
    for (size_t k = 0; k < bodies_.size(); ++k) bodies_[k].reaction = r[k];
  }

  // The bodies' state (pose, velocities, last reaction) for a checkpoint, and back; a state of
  // another number of bodies is refused.
  std::vector<double> saved() const {
    std::vector<double> out;
    for (const Body& b : bodies_) {
      out.insert(out.end(), b.center.begin(), b.center.end());
      out.insert(out.end(), b.velocity.begin(), b.velocity.end());
      out.insert(out.end(), b.rotation.begin(), b.rotation.end());
      out.insert(out.end(), b.momentum.begin(), b.momentum.end());
      const Wrench& w = b.reaction;
      out.insert(out.end(), {w.fx, w.fy, w.fz, w.tx, w.ty, w.tz});
    }
    return out;
  }
  void restore(const std::vector<double>& in) {
    if (in.size() != kSavedPerBody * bodies_.size())
      throw std::invalid_argument("the checkpoint holds " + std::to_string(in.size() / kSavedPerBody) +
                                  " free colliders, the scene " + std::to_string(bodies_.size()));
    const double* v = in.data();
    auto take = [&v](auto& array) {
      for (double& x : array) x = *v++;
    };
    for (Body& b : bodies_) {
      take(b.center);
      take(b.velocity);
      take(b.rotation);
      take(b.momentum);
      Wrench& w = b.reaction;
      for (double* x : {&w.fx, &w.fy, &w.fz, &w.tx, &w.ty, &w.tz}) *x = *v++;
    }
  }

  // Half a step of the reaction and gravity on the momenta.
  void kick(double half_dt, const Vec3& gravity) {
    for (Body& b : bodies_) {
      const double g[3] = {double(gravity.x), double(gravity.y), double(gravity.z)};
      const double f[3] = {b.reaction.fx, b.reaction.fy, b.reaction.fz};
      const double t[3] = {b.reaction.tx, b.reaction.ty, b.reaction.tz};
      for (int a = 0; a < 3; ++a) {
        b.velocity[size_t(a)] += half_dt * (f[a] / b.mass + g[a]);
        b.momentum[size_t(a)] += half_dt * t[a];
      }
    }
  }

  // A step of the pose at the current velocities.
  void drift(double dt) {
    for (Body& b : bodies_) {
      for (int a = 0; a < 3; ++a) b.center[size_t(a)] += dt * b.velocity[size_t(a)];
      const std::array<double, 9> turn = rotation_minus_identity(angular_velocity(b), dt);
      std::array<double, 9> r = b.rotation;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          for (int q = 0; q < 3; ++q)
            r[size_t(3 * i + j)] += turn[size_t(3 * i + q)] * b.rotation[size_t(3 * q + j)];
      b.rotation = r;
    }
  }

 private:
  static constexpr size_t kSavedPerBody = 24;
  struct Body {
    int64_t collider = 0;
    double mass = 0;
    std::array<double, 3> inertia{0, 0, 0};  // principal, about the shape's axes
    std::array<double, 3> center{0, 0, 0}, velocity{0, 0, 0};
    std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // shape frame to world
    std::array<double, 3> momentum{0, 0, 0};                    // angular, about the centre
    Wrench reaction;
  };

  static Vec3 to_real(const std::array<double, 3>& v) { return {real(v[0]), real(v[1]), real(v[2])}; }

  // R diag(I) R^T w, and its inverse applied to the angular momentum.
  static std::array<double, 3> world_inertia_times(const Body& b, const std::array<double, 3>& w) {
    return in_world(b, w, false);
  }
  static std::array<double, 3> angular_velocity(const Body& b) { return in_world(b, b.momentum, true); }
  static std::array<double, 3> in_world(const Body& b, const std::array<double, 3>& v, bool inverse) {
    const auto& r = b.rotation;
    double local[3];
    for (int j = 0; j < 3; ++j) {  // R^T v, scaled by I (or 1 / I) about each shape axis
      local[j] = r[size_t(j)] * v[0] + r[size_t(3 + j)] * v[1] + r[size_t(6 + j)] * v[2];
      const double i = b.inertia[size_t(j)];
      local[j] = inverse ? (i > 0 ? local[j] / i : 0) : local[j] * i;
    }
    std::array<double, 3> out{};
    for (int i = 0; i < 3; ++i)
      out[size_t(i)] =
          r[size_t(3 * i)] * local[0] + r[size_t(3 * i + 1)] * local[1] + r[size_t(3 * i + 2)] * local[2];
    return out;
  }

  std::vector<Body> bodies_;
  std::vector<double> masses_;  // per collider; 0 where not free
};

}  // namespace pd
