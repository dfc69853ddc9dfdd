// Scripted motion of anchors and projectiles: keyframed paths, rotations and releases,
// evaluated on the host once per step into the StepParams the kernels read (views.h:
// AnchorMotion, Projectile). Times are simulation seconds.
#pragma once

#include <array>
#include <limits>
#include <vector>

#include "cuda/views.h"

namespace pd {

// A point on a path at time t: {t, x, y, z}.
using Keyframe = std::array<double, 4>;

// Piecewise-linear path through keyframes of increasing time. Before the first keyframe it
// rests at the first point, after the last at the last; in between it moves along the segment
// at the segment's velocity.
struct PathSample {
  std::array<double, 3> position{0, 0, 0};
  std::array<double, 3> velocity{0, 0, 0};
};
PathSample sample_path(const std::vector<Keyframe>& path, double t);

// One anchor group. Unscripted (no path, no rotation): its particles keep the velocity they
// started with. Scripted: a rigid motion of the rest configuration about `pivot`, translated
// by the path (or by velocity * t) and turned at the constant angular velocity `omega`.
struct AnchorScript {
  std::array<double, 3> pivot{0, 0, 0};     // rest-space centre of rotation [m]
  std::array<double, 3> velocity{0, 0, 0};  // constant translation when there is no path [m/s]
  std::vector<Keyframe> path;               // translation offsets from the rest pose [s, m, m, m]
  std::array<double, 3> omega{0, 0, 0};     // angular velocity [rad/s]
  double release = std::numeric_limits<double>::infinity();  // from this time on the particles are free
  bool scripted() const { return !path.empty() || omega[0] != 0 || omega[1] != 0 || omega[2] != 0; }
};

// One collider's motion: fixed (no velocity, path or rotation), or its centre moving at a
// constant velocity or along a keyframed path, and its shape turning about the centre at a
// constant angular velocity from its initial orientation.
struct ColliderScript {
  std::array<double, 3> center{0, 0, 0};                      // at t = 0 [m]
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // at t = 0, shape frame to world
  std::array<double, 3> velocity{0, 0, 0};                    // constant, when there is no path [m/s]
  std::vector<Keyframe> path;                                 // keyframed centre [s, m, m, m]
  std::array<double, 3> omega{0, 0, 0};                       // angular velocity [rad/s]
  // A free rigid body (mass > 0): `velocity` and `omega` are its initial ones, then the particles'
  // reaction and gravity move it (FreeBodies, cuda/engine/free_bodies.h); no path.
  double mass = 0;                         // [kg]
  std::array<double, 3> inertia{0, 0, 0};  // principal moments about the shape's axes [kg m^2]
  bool free() const { return mass > 0; }
  bool moves() const {
    return free() || !path.empty() || velocity != std::array<double, 3>{0, 0, 0} ||
           omega != std::array<double, 3>{0, 0, 0};
  }
};

struct MotionScript {
  std::vector<AnchorScript> anchors;               // at most kMaxAnchors, indexed by anchor group
  std::vector<std::vector<Keyframe>> projectiles;  // per projectile; empty: its constant velocity
  std::vector<ColliderScript> colliders;           // one per collider of SimulationInput::colliders

  bool empty() const;
  // Writes the anchors' and keyframed projectiles' state at time t into `sp`.
  void apply(double t, StepParams& sp) const;
  bool colliders_move() const;
  // Sets each scripted collider's pose and velocity at time t (its shape and contact law kept;
  // free ones are left to FreeBodies).
  void pose_colliders(double t, std::vector<Collider>& colliders) const;
};

// R - I for the rotation by the angle |w| t about w (Rodrigues), row major, without the
// cancellation of forming R and subtracting I: R - I = sin(a) K + 2 sin^2(a/2) K^2.
std::array<double, 9> rotation_minus_identity(const std::array<double, 3>& omega, double t);

}  // namespace pd
