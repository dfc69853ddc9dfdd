#include "cuda/engine/motion.h"

#include <algorithm>
#include <cmath>

namespace pd {

namespace {

Vec3 to_vec3(const std::array<double, 3>& v) {
  return {real(v[0]), real(v[1]), real(v[2])};
}

}  // namespace

PathSample sample_path(const std::vector<Keyframe>& path, double t) {
  PathSample s;
  if (path.empty()) return s;
  const auto point = [&](size_t k) { return std::array<double, 3>{path[k][1], path[k][2], path[k][3]}; };
  if (t <= path.front()[0]) {
    s.position = point(0);
    return s;
  }
  if (t >= path.back()[0]) {
    s.position = point(path.size() - 1);
    return s;
  }
  // The segment [k, k + 1] holding t: the first keyframe later than t ends it.
  const auto later = std::upper_bound(path.begin(), path.end(), t,
                                      [](double time, const Keyframe& key) { return time < key[0]; });
  const size_t k = size_t(later - path.begin()) - 1;
  const double span = path[k + 1][0] - path[k][0], f = (t - path[k][0]) / span;
  for (int c = 0; c < 3; ++c) {
    const double a = path[k][c + 1], b = path[k + 1][c + 1];
    s.position[c] = a + f * (b - a);
    s.velocity[c] = (b - a) / span;
  }
  return s;
}

std::array<double, 9> rotation_minus_identity(const std::array<double, 3>& omega, double t) {
  const double rate = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
  std::array<double, 9> m{};
  if (rate == 0) return m;
  const double angle = rate * t, x = omega[0] / rate, y = omega[1] / rate, z = omega[2] / rate;
  const double k[9] = {0, -z, y, z, 0, -x, -y, x, 0};  // the cross-product matrix of the unit axis
  const double s = std::sin(angle), h = std::sin(0.5 * angle), c = 2 * h * h;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) {
      double k2 = 0;
      for (int j = 0; j < 3; ++j) k2 += k[3 * r + j] * k[3 * j + col];
      m[size_t(3 * r + col)] = s * k[3 * r + col] + c * k2;
    }
  return m;
}

bool MotionScript::empty() const {
  if (!std::all_of(projectiles.begin(), projectiles.end(), [](const auto& p) { return p.empty(); }))
    return false;
  return std::all_of(anchors.begin(), anchors.end(),
                     [](const AnchorScript& a) { return !a.scripted() && !std::isfinite(a.release); });
}

void MotionScript::apply(double t, StepParams& sp) const {
  for (size_t g = 0; g < anchors.size() && g < size_t(kMaxAnchors); ++g) {
    const AnchorScript& a = anchors[g];
    AnchorMotion& m = sp.anchor[g];
    m.released = t >= a.release ? 1 : 0;
    m.scripted = a.scripted() ? 1 : 0;
    if (!m.scripted) continue;
    const PathSample move =
        a.path.empty() ? PathSample{{a.velocity[0] * t, a.velocity[1] * t, a.velocity[2] * t}, a.velocity}
                       : sample_path(a.path, t);
    m.pivot = to_vec3(a.pivot);
    m.offset = to_vec3(move.position);
    m.velocity = to_vec3(move.velocity);
    m.omega = to_vec3(a.omega);
    const auto rm = rotation_minus_identity(a.omega, t);
    for (int k = 0; k < 9; ++k) m.rotation_minus_identity[k] = real(rm[size_t(k)]);
  }
  // A keyframed projectile: centre0 + t velocity is the path on the segment holding t.
  for (size_t k = 0; k < projectiles.size() && k < size_t(kMaxProjectiles); ++k) {
    if (projectiles[k].empty()) continue;
    const PathSample s = sample_path(projectiles[k], t);
    Projectile& p = sp.projectile[k];
    p.velocity = to_vec3(s.velocity);
    p.center0 = to_vec3({s.position[0] - t * s.velocity[0], s.position[1] - t * s.velocity[1],
                         s.position[2] - t * s.velocity[2]});
  }
}

bool MotionScript::colliders_move() const {
  return std::any_of(colliders.begin(), colliders.end(), [](const ColliderScript& c) { return c.moves(); });
}

void MotionScript::pose_colliders(double t, std::vector<Collider>& out) const {
  for (size_t k = 0; k < colliders.size() && k < out.size(); ++k) {
    const ColliderScript& c = colliders[k];
    if (c.free()) continue;
    const PathSample move =
        c.path.empty() ? PathSample{{c.center[0] + c.velocity[0] * t, c.center[1] + c.velocity[1] * t,
                                     c.center[2] + c.velocity[2] * t},
                                    c.velocity}
                       : sample_path(c.path, t);
    Collider& o = out[k];
    o.center = to_vec3(move.position);
    o.velocity = to_vec3(move.velocity);
    o.omega = to_vec3(c.omega);
    // R(t) R0 with R(t) = I + (R - I) (rotation_minus_identity keeps a small turn's digits).
    const auto turn = rotation_minus_identity(c.omega, t);
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) {
        double v = c.rotation[size_t(3 * r + col)];
        for (int j = 0; j < 3; ++j) v += turn[size_t(3 * r + j)] * c.rotation[size_t(3 * j + col)];
        o.rotation[3 * r + col] = real(v);
      }
  }
}

}  // namespace pd
