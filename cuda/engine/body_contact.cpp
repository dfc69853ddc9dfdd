// Contact between rigid colliders (body_contact.h).
#include "cuda/engine/body_contact.h"

#include <algorithm>
#include <cmath>

namespace pd {
namespace {

constexpr int kRimPoints = 24;     // per rim of a cylinder
constexpr int kCapsulePoints = 5;  // along a capsule's segment

// Which of a pair probes: the lower rank (a sphere before a capsule before a box or cylinder);
// a plane never does.
int probe_rank(const Collider& c) {
  switch (c.shape) {
    case kColliderSphere:
      return 0;
    case kColliderCapsule:
      return 1;
    case kColliderPlane:
      return 3;
    default:
      return 2;
  }
}

Vec3 to_world(const Collider& c, Vec3 q) {
  const real* m = c.rotation;
  return c.center + Vec3{m[0] * q.x + m[1] * q.y + m[2] * q.z, m[3] * q.x + m[4] * q.y + m[5] * q.z,
                         m[6] * q.x + m[7] * q.y + m[8] * q.z};
}

Vec3 point_velocity(const Collider& c, Vec3 p) {
  return c.velocity + cross(c.omega, p - c.center);
}

void add_force(Wrench& w, const Collider& c, Vec3 point, Vec3 f) {
  const Vec3 t = cross(point - c.center, f);
  w = w + Wrench{double(f.x), double(f.y), double(f.z), double(t.x), double(t.y), double(t.z)};
}

// The forces of `surface` on the probes of `prober` (and their reactions), added to both wrenches.
void probe_pair(const Collider& prober, const std::vector<Probe>& probes, const Collider& surface,
                const float* grids, double reduced_mass, double dt, Wrench& on_prober, Wrench& on_surface) {
  struct Touch {
    Vec3 point, normal;
    real depth;
  };
  std::vector<Touch> touches;
  for (const Probe& probe : probes) {
    const Vec3 q = to_world(prober, probe.point);
    const SurfacePoint s = collider_surface(surface, q, grids);
    const real depth = probe.radius - s.distance;
    if (depth > real(0)) touches.push_back({q - probe.radius * s.normal, s.normal, depth});
  }
  if (touches.empty()) return;
  const double k = double(std::min(prober.stiffness, surface.stiffness)) * probe_length(prober);
  const double damping = 2 * double(std::max(prober.damping, surface.damping)) * std::sqrt(k * reduced_mass);
  const double mu_static = 0.5 * double(prober.friction_static + surface.friction_static);
  const double mu_dynamic = 0.5 * double(prober.friction_dynamic + surface.friction_dynamic);
  const double share = reduced_mass / (dt * double(touches.size()));  // each probe's part of stopping
  for (const Touch& t : touches) {
    const Vec3 relative = point_velocity(prober, t.point) - point_velocity(surface, t.point);
    const double approach = double(dot(relative, t.normal));  // > 0: separating
    const double push = std::max(k * double(t.depth) - damping * approach, 0.0);
    if (push == 0) continue;
    Vec3 f = real(push) * t.normal;
    const Vec3 slide = relative - real(approach) * t.normal;
    const double speed = double(length(slide));
    if (speed > 0) {
      const double stop = share * speed;
      const double friction = stop <= mu_static * push ? stop : mu_dynamic * push;
      f -= real(friction / speed) * slide;
    }
    add_force(on_prober, prober, t.point, f);
    add_force(on_surface, surface, t.point, -f);
  }
}

bool touches_bodies(const Collider& c) {
  return c.law == kLawPenalty;
}

}  // namespace

std::vector<Probe> shape_probes(const Collider& c, const MeshShapes& meshes, size_t k) {
  std::vector<Probe> probes;
  const Vec3 h = c.size;
  switch (c.shape) {
    case kColliderMesh:
      if (meshes.probes && k < meshes.probes->size())
        for (const Vec3& p : (*meshes.probes)[k]) probes.push_back({p, 0});
      break;
    case kColliderSphere:
      probes.push_back({{0, 0, 0}, h.x});
      break;
    case kColliderCapsule:
      for (int i = 0; i < kCapsulePoints; ++i)
        probes.push_back({{0, h.y * real(2 * i - (kCapsulePoints - 1)) / real(kCapsulePoints - 1), 0}, h.x});
      break;
    case kColliderBox:
      for (int a = -1; a <= 1; ++a)  // the corners (no zero) and edge midpoints (one zero)
        for (int b = -1; b <= 1; ++b)
          for (int e = -1; e <= 1; ++e)
            if ((a == 0) + (b == 0) + (e == 0) <= 1)
              probes.push_back({{real(a) * h.x, real(b) * h.y, real(e) * h.z}, 0});
      break;
    case kColliderCylinder:
      for (int end = -1; end <= 1; end += 2)
        for (int i = 0; i < kRimPoints; ++i) {
          const double angle = 2 * M_PI * i / kRimPoints;
          probes.push_back({{real(h.x * std::cos(angle)), real(end) * h.y, real(h.x * std::sin(angle))}, 0});
        }
      break;
    default:  // a plane
      break;
  }
  return probes;
}

double probe_length(const Collider& c) {
  if (c.shape == kColliderBox || c.shape == kColliderMesh)
    return double(std::min(c.size.x, std::min(c.size.y, c.size.z)));
  return double(c.size.x);  // a radius
}

std::vector<Wrench> body_contact_wrenches(const std::vector<Collider>& colliders,
                                          const std::vector<double>& masses, double dt,
                                          const MeshShapes& meshes) {
  std::vector<Wrench> out(colliders.size());
  for (size_t a = 0; a < colliders.size(); ++a)
    for (size_t b = a + 1; b < colliders.size(); ++b) {
      if (masses[a] <= 0 && masses[b] <= 0) continue;
      const Collider &ca = colliders[a], &cb = colliders[b];
      if (!touches_bodies(ca) || !touches_bodies(cb)) continue;
      const int ra = probe_rank(ca), rb = probe_rank(cb);
      if (ra == 3 && rb == 3) continue;
      const double reduced = masses[a] > 0 && masses[b] > 0 ? masses[a] * masses[b] / (masses[a] + masses[b])
                                                            : std::max(masses[a], masses[b]);
      if (ra <= rb)
        probe_pair(ca, shape_probes(ca, meshes, a), cb, meshes.grids, reduced, dt, out[a], out[b]);
      if (rb < ra || (ra == 2 && rb == 2))
        probe_pair(cb, shape_probes(cb, meshes, b), ca, meshes.grids, reduced, dt, out[b], out[a]);
    }
  return out;
}

double body_contact_rate(const std::vector<Collider>& colliders, const std::vector<double>& masses,
                         const MeshShapes& meshes) {
  double rate = 0;
  for (size_t a = 0; a < colliders.size(); ++a)
    for (size_t b = 0; b < colliders.size(); ++b) {
      if (a == b || masses[a] <= 0 || !touches_bodies(colliders[a]) || !touches_bodies(colliders[b]))
        continue;
      const double reduced = masses[b] > 0 ? masses[a] * masses[b] / (masses[a] + masses[b]) : masses[a];
      const double stiffness = double(std::min(colliders[a].stiffness, colliders[b].stiffness));
      for (const size_t p : {a, b}) {
        const Collider& prober = colliders[p];
        const double k = stiffness * probe_length(prober) * double(shape_probes(prober, meshes, p).size());
        rate = std::max(rate, std::sqrt(k / reduced));
      }
    }
  return rate;
}

}  // namespace pd
