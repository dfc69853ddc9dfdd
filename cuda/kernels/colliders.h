// Rigid colliders in `bodyforces` (kernel 5): each analytic shape (views.h Collider) pushes the
// particles that reach into it. A particle is a ball of radius a = V^(1/3) / 2; pressed in by d
// (its centre within a of the surface, or inside) it feels the penalty K V^(1/3) d along the
// surface normal, less the damping of the normal push (c = 2 zeta sqrt(k m)), never pulling;
// and Coulomb friction against its velocity relative to the surface: the force that stops the
// sliding within a step while that stays within mu_s times the push, else mu_d times the push.
// Or LAMMPS's `fix indent` law (kLawLammpsIndent): a particle whose centre is d inside the shape
// feels K d^2 V along the normal, with no damping or friction. LAMMPS's peridynamic atoms carry
// force densities and a mass density (atom_style peri), so `fix indent`'s K d^2 is per unit volume
// there: K [N/m^5] under `units si`, the same number as in the LAMMPS input.
#pragma once

#include <cmath>

#include "cuda/views.h"

namespace pd {

// Signed distance from the shape's surface (negative inside) and the outward unit normal, at a
// point q in the shape's frame.
struct SurfacePoint {
  real distance;
  Vec3 normal;
};

PD_HD inline real clamp_real(real x, real lo, real hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}

// A direction from q (or `fallback` at q = 0).
PD_HD inline Vec3 unit_or(Vec3 q, Vec3 fallback) {
  const real len = length(q);
  return len > real(0) ? (real(1) / len) * q : fallback;
}

PD_HD inline SurfacePoint box_surface(Vec3 q, Vec3 h) {
  const Vec3 a{std::abs(q.x) - h.x, std::abs(q.y) - h.y, std::abs(q.z) - h.z};
  const Vec3 sign{q.x < 0 ? real(-1) : real(1), q.y < 0 ? real(-1) : real(1), q.z < 0 ? real(-1) : real(1)};
  if (a.x > 0 || a.y > 0 || a.z > 0) {  // outside: from the nearest point of the box
    const Vec3 out{a.x > 0 ? a.x * sign.x : real(0), a.y > 0 ? a.y * sign.y : real(0),
                   a.z > 0 ? a.z * sign.z : real(0)};
    const real d = length(out);
    return {d, (real(1) / d) * out};
  }
  // Inside: through the nearest face.
  if (a.x >= a.y && a.x >= a.z) return {a.x, {sign.x, 0, 0}};
  if (a.y >= a.z) return {a.y, {0, sign.y, 0}};
  return {a.z, {0, 0, sign.z}};
}

PD_HD inline SurfacePoint cylinder_surface(Vec3 q, real radius, real half) {
  const real r = std::sqrt(q.x * q.x + q.z * q.z);
  const Vec3 radial = r > real(0) ? Vec3{q.x / r, 0, q.z / r} : Vec3{1, 0, 0};
  const Vec3 axial{0, q.y < 0 ? real(-1) : real(1), 0};
  const real dr = r - radius, dy = std::abs(q.y) - half;
  if (dr > 0 && dy > 0) {  // beyond the rim
    const real d = std::sqrt(dr * dr + dy * dy);
    return {d, (dr / d) * radial + (dy / d) * axial};
  }
  if (dr > dy) return {dr, radial};
  return {dy, axial};
}

// The cell of a grid of n nodes (n >= 2) holding coordinate g in [0, n - 1].
PD_HD inline int32_t cell_below(real g, int32_t n) {
  const int32_t i = int32_t(g);
  return i < n - 2 ? i : n - 2;
}

// A mesh collider's surface from its distance grid: trilinear interpolation of the 8 nodes around
// q and the gradient of that interpolation as the normal. Outside the grid the distance grows by
// how far q is from it.
PD_HD inline SurfacePoint grid_surface(const Collider& c, Vec3 q, const float* grids) {
  const int32_t nx = c.grid_dims[0], ny = c.grid_dims[1], nz = c.grid_dims[2];
  const real inv = real(1) / c.grid_cell;
  const Vec3 g = inv * (q - c.grid_origin);
  const Vec3 in{clamp_real(g.x, 0, real(nx - 1)), clamp_real(g.y, 0, real(ny - 1)),
                clamp_real(g.z, 0, real(nz - 1))};
  const int32_t i = cell_below(in.x, nx), j = cell_below(in.y, ny), k = cell_below(in.z, nz);
  const real fx = in.x - real(i), fy = in.y - real(j), fz = in.z - real(k);
  const int64_t sy = nx, sz = int64_t(nx) * ny;
  const float* v = grids + c.grid_offset + i + sy * j + sz * k;
  const real c000 = v[0], c100 = v[1], c010 = v[sy], c110 = v[sy + 1];
  const real c001 = v[sz], c101 = v[sz + 1], c011 = v[sz + sy], c111 = v[sz + sy + 1];
  const real c00 = c000 + fx * (c100 - c000), c10 = c010 + fx * (c110 - c010);
  const real c01 = c001 + fx * (c101 - c001), c11 = c011 + fx * (c111 - c011);
  const real c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
  const Vec3 gradient{(1 - fy) * (1 - fz) * (c100 - c000) + fy * (1 - fz) * (c110 - c010) +
                          (1 - fy) * fz * (c101 - c001) + fy * fz * (c111 - c011),
                      (1 - fx) * (1 - fz) * (c010 - c000) + fx * (1 - fz) * (c110 - c100) +
                          (1 - fx) * fz * (c011 - c001) + fx * fz * (c111 - c101),
                      c1 - c0};
  const Vec3 beyond = c.grid_cell * (g - in);
  return {c0 + fz * (c1 - c0) + length(beyond), unit_or(gradient, unit_or(beyond, {0, 1, 0}))};
}

PD_HD inline SurfacePoint shape_surface(const Collider& c, Vec3 q, const float* grids = nullptr) {
  switch (c.shape) {
    case kColliderMesh:
      if (!grids) return {real(1e30), {0, 1, 0}};  // (no grid given: far from everything)
      return grid_surface(c, q, grids);
    case kColliderSphere:
      return {length(q) - c.size.x, unit_or(q, {0, 1, 0})};
    case kColliderBox:
      return box_surface(q, c.size);
    case kColliderCapsule: {
      const Vec3 d = q - Vec3{0, clamp_real(q.y, -c.size.y, c.size.y), 0};
      return {length(d) - c.size.x, unit_or(d, {1, 0, 0})};
    }
    case kColliderCylinder:
      return cylinder_surface(q, c.size.x, c.size.y);
    default:  // kColliderPlane
      return {q.y, {0, 1, 0}};
  }
}

// The shape's surface at world point x: distance and world normal.
PD_HD inline SurfacePoint collider_surface(const Collider& c, Vec3 x, const float* grids = nullptr) {
  const real* m = c.rotation;
  const Vec3 d = x - c.center;
  const Vec3 q{m[0] * d.x + m[3] * d.y + m[6] * d.z, m[1] * d.x + m[4] * d.y + m[7] * d.z,
               m[2] * d.x + m[5] * d.y + m[8] * d.z};  // R^T (x - centre)
  const SurfacePoint s = shape_surface(c, q, grids);
  const Vec3 n{m[0] * s.normal.x + m[1] * s.normal.y + m[2] * s.normal.z,
               m[3] * s.normal.x + m[4] * s.normal.y + m[5] * s.normal.z,
               m[6] * s.normal.x + m[7] * s.normal.y + m[8] * s.normal.z};
  return {s.distance, n};
}

// The force of collider c on a particle of size h = V^(1/3) at x with velocity v and mass `mass`
// over a step of dt (`grids`: the mesh colliders' distance grids). A particle farther from the
// centre than the shape's bounding radius and its own reach h/2 is not touched (no distance taken).
// Whether a particle of size h at x is beyond the reach of a collider of that centre and bounding
// radius (0 or less: unbounded).
PD_HD inline bool out_of_reach(Vec3 x, real size, Vec3 center, real bound) {
  if (!(bound > 0)) return false;
  const real reach = real(1.0001) * bound + real(0.5) * size;
  return length_squared(x - center) > reach * reach;
}

// (`checked`: the caller has found the particle within reach.)
PD_HD inline Vec3 collider_push(const Collider& c, Vec3 x, Vec3 v, real size, real mass, real dt,
                                const float* grids, bool checked = false) {
  if (!checked && out_of_reach(x, size, c.center, c.bound)) return {0, 0, 0};
  const SurfacePoint s = collider_surface(c, x, grids);
  if (c.law == kLawLammpsIndent) {
    const real inside = -s.distance;
    return inside > real(0) ? (c.stiffness * inside * inside * size * size * size) * s.normal : Vec3{0, 0, 0};
  }
  const real depth = real(0.5) * size - s.distance;
  if (!(depth > real(0))) return {0, 0, 0};
  const Vec3 relative = v - (c.velocity + cross(c.omega, x - c.center));
  const real approach = dot(relative, s.normal);  // > 0: separating
  const real k = c.stiffness * size;
  const real push = max_of(k * depth - real(2) * c.damping * std::sqrt(k * mass) * approach, real(0));
  Vec3 f = push * s.normal;
  const Vec3 slide = relative - approach * s.normal;
  const real speed = length(slide);
  if (speed > real(0) && push > real(0)) {
    const real stop = mass * speed / dt;  // the force that ends the sliding within the step
    const real friction = stop <= c.friction_static * push ? stop : c.friction_dynamic * push;
    f -= (friction / speed) * slide;
  }
  return f;
}

// The same for a particle of volume `volume`.
PD_HD inline Vec3 collider_force(const Collider& c, Vec3 x, Vec3 v, real volume, real mass, real dt,
                                 const float* grids = nullptr) {
  return collider_push(c, x, v, std::cbrt(volume), mass, dt, grids);
}

// Every collider's force on particle i.
PD_HD inline Vec3 colliders_force(int32_t i, const ParticlesView& p, const StepParams& sp) {
  Vec3 f{0, 0, 0};
  const int64_t count = sp.colliders.size;
  if (count == 0) return f;
  const Vec3 x = p.position(i), v = p.vel[i];
  const real mass = real(1) / p.inv_mass[i], size = std::cbrt(p.volume(i));
  const ColliderGridView& g = sp.collider_grid;
  const ArrayView<const int32_t> lists = g.lists;
  for (int64_t j = g.unbounded; j < lists.size; ++j)  // planes
    f += collider_push(sp.colliders[lists[j]], x, v, size, mass, sp.dt, sp.collider_grids.data(), true);
  const Vec3 q = g.inv_cell * (x - g.lo);
  const real top = real(g.dims);
  if (!(q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < top && q.y < top && q.z < top)) return f;
  const int32_t cell = (int32_t(q.z) * g.dims + int32_t(q.y)) * g.dims + int32_t(q.x);
  for (int32_t j = lists[cell]; j < lists[cell + 1]; ++j) {
    const int32_t k = lists[j];
    const Vec4 sphere = sp.collider_spheres[k];
    if (out_of_reach(x, size, xyz(sphere), sphere.w)) continue;
    f += collider_push(sp.colliders[k], x, v, size, mass, sp.dt, sp.collider_grids.data(), true);
  }
  return f;
}

// What the particles do to a free collider: the sum of the reactions to its forces, and their
// moment about its centre (double sums, added in the backend's reduction order).
struct Wrench {
  double fx = 0, fy = 0, fz = 0;  // force [N]
  double tx = 0, ty = 0, tz = 0;  // torque about the centre [N m]
};

PD_HD inline Wrench operator+(const Wrench& a, const Wrench& b) {
  return {a.fx + b.fx, a.fy + b.fy, a.fz + b.fz, a.tx + b.tx, a.ty + b.ty, a.tz + b.tz};
}

// Particle i's reaction on collider c: minus the force c puts on it (as bodyforces computed it).
PD_HD inline Wrench collider_reaction(int32_t i, const ParticlesView& p, const Collider& c, real dt,
                                      const float* grids) {
  const Vec3 x = p.position(i);
  const Vec3 f = collider_force(c, x, p.vel[i], p.volume(i), real(1) / p.inv_mass[i], dt, grids);
  if (f.x == 0 && f.y == 0 && f.z == 0) return {};
  const Vec3 r = x - c.center;
  const Vec3 t = cross(r, f);
  return {-double(f.x), -double(f.y), -double(f.z), -double(t.x), -double(t.y), -double(t.z)};
}

}  // namespace pd
