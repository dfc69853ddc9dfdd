#include "host/scene/collider_setup.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "cuda/engine/body_contact.h"
#include "cuda/engine/free_bodies.h"
#include "cuda/kernels/colliders.h"
#include "host/geometry/distance_grid.h"
#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"

namespace pd {
namespace {

Vec3 to_real(const Vec3d& v) {
  return {real(v[0]), real(v[1]), real(v[2])};
}

// A distance grid of more nodes is refused (2^25 floats: 128 MiB).
constexpr int64_t kMaxGridNodes = int64_t(1) << 25;

// A free collider's mass (given, or its density times its volume) and principal moments of
// inertia about its axes (its y axis the capsule's and cylinder's).
void set_mass_and_inertia(const SceneCollider& sc, ColliderScript& s) {
  const double pi = 3.14159265358979323846, r = sc.radius, l = sc.length;
  const double hx = 0.5 * sc.size[0], hy = 0.5 * sc.size[1], hz = 0.5 * sc.size[2];
  double volume = 0;
  if (sc.shape == "sphere") volume = 4.0 / 3.0 * pi * r * r * r;
  if (sc.shape == "box") volume = 8 * hx * hy * hz;
  if (sc.shape == "cylinder") volume = pi * r * r * l;
  if (sc.shape == "capsule") volume = pi * r * r * l + 4.0 / 3.0 * pi * r * r * r;
  const double m = sc.mass ? *sc.mass : *sc.density * volume;
  s.mass = m;
  if (sc.shape == "sphere") s.inertia = {0.4 * m * r * r, 0.4 * m * r * r, 0.4 * m * r * r};
  if (sc.shape == "box")
    s.inertia = {m / 3 * (hy * hy + hz * hz), m / 3 * (hx * hx + hz * hz), m / 3 * (hx * hx + hy * hy)};
  if (sc.shape == "cylinder") {
    const double across = m * (3 * r * r + l * l) / 12;
    s.inertia = {across, 0.5 * m * r * r, across};
  }
  if (sc.shape == "capsule") {  // the cylinder and the two hemispheres (at their centroids 3r/8 out)
    const double mc = m * pi * r * r * l / volume, ms = m - mc;
    const double across = mc * (l * l / 12 + r * r / 4) + ms * (0.4 * r * r + l * l / 4 + 3 * l * r / 8);
    s.inertia = {across, 0.5 * mc * r * r + 0.4 * ms * r * r, across};
  }
}

// A mesh collider: the file read and scaled, closed (a solid, signed distance) or open (a sheet,
// pushing from both sides); moved into its frame (the volume centroid of a solid, turned onto its
// principal axes when free; the bounding-box centre of a sheet); its distance grid, probes and,
// when free, mass and inertia.
struct MeshCollider {
  TriMesh mesh;  // in its frame
  bool closed = true;
  std::array<double, 9> axes{1, 0, 0, 0, 1, 0, 0, 0, 1};  // its frame in the file's, row major
};

MeshCollider mesh_collider(const SceneCollider& sc, const std::string& key, const Scene& scene,
                           ColliderScript& script) {
  MeshCollider out;
  TriMesh mesh;
  bool closed = true;
  try {  // a broken file is named with the scene and its key, as a body's mesh is
    mesh = read_mesh(sc.mesh_path);
    for (Vec3d& v : mesh.vertices) v = sc.scale * v;
    try {
      TriMesh checked = mesh;
      check_solid(checked, sc.mesh_path, {});
      mesh = std::move(checked);
    } catch (const MeshError& e) {
      if (std::string(e.what()).find("the mesh is open") == std::string::npos) throw;
      closed = false;
    }
  } catch (const MeshError& e) {
    throw SceneError(scene.path, key + ".mesh", e.what());
  }
  const bool free = sc.mass || sc.density;
  if (free && !closed)
    throw SceneError(scene.path, key + ".mesh",
                     "'" + sc.mesh_path +
                         "' is an open mesh, which has no volume to move as a free body "
                         "(allowed: a closed mesh for a free collider; an open sheet fixed or scripted)");
  Vec3d origin = bounds(mesh).center();
  if (closed) {
    const MassProperties m = mass_properties(mesh);
    origin = m.centroid;
    if (free) {
      Eigen::Matrix3d inertia;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) inertia(i, j) = m.inertia[size_t(3 * i + j)];
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(inertia);
      Eigen::Matrix3d axes = solver.eigenvectors();
      if (axes.determinant() < 0) axes.col(2) *= -1;  // a rotation, not a reflection
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out.axes[size_t(3 * i + j)] = axes(i, j);
      const double mass = sc.mass ? *sc.mass : *sc.density * m.volume;
      script.mass = mass;
      for (int a = 0; a < 3; ++a) script.inertia[size_t(a)] = mass / m.volume * solver.eigenvalues()(a);
    }
  }
  // Vertices into the frame: x' = A^T (x - origin).
  for (Vec3d& v : mesh.vertices) {
    const Vec3d d = v - origin;
    const auto& a = out.axes;
    v = {a[0] * d[0] + a[3] * d[1] + a[6] * d[2], a[1] * d[0] + a[4] * d[1] + a[7] * d[2],
         a[2] * d[0] + a[5] * d[1] + a[8] * d[2]};
  }
  out.mesh = std::move(mesh);
  out.closed = closed;
  return out;
}

// The default grid spacing: half the smallest particle's size, but no finer than the mesh's
// longest extent / 256.
double default_cell(const TriMesh& mesh, const SimulationInput& in) {
  double smallest = HUGE_VAL;
  for (real v : in.particles.volume) smallest = std::min(smallest, std::cbrt(double(v)));
  const Vec3d extent = bounds(mesh).size();
  const double longest = std::max({extent[0], extent[1], extent[2]});
  if (!(smallest < HUGE_VAL)) smallest = longest / 64;
  return std::max(0.5 * smallest, longest / 256);
}

// The product of two row-major rotations.
std::array<double, 9> times(const std::array<double, 9>& a, const std::array<double, 9>& b) {
  std::array<double, 9> r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int q = 0; q < 3; ++q) r[size_t(3 * i + j)] += a[size_t(3 * i + q)] * b[size_t(3 * q + j)];
  return r;
}

// The mesh collider's grid, frame, probes and size into the engine's input.
void add_mesh_collider(const SceneCollider& sc, const std::string& key, const Scene& scene,
                       SimulationInput& in, Collider& c, ColliderScript& script,
                       std::vector<TriMesh>& meshes) {
  MeshCollider m = mesh_collider(sc, key, scene, script);
  script.rotation = times(script.rotation, m.axes);
  const double cell = sc.cell.value_or(default_cell(m.mesh, in));
  double largest = 0;
  for (real v : in.particles.volume) largest = std::max(largest, std::cbrt(double(v)));
  const double margin = 0.5 * largest + 2 * cell;
  const int64_t nodes = distance_grid_nodes(m.mesh, cell, margin);
  if (nodes > kMaxGridNodes) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", cell);
    throw SceneError(scene.path, key + ".cell",
                     std::string("a grid spacing of ") + text + " m gives the mesh's distance grid " +
                         std::to_string(nodes) + " nodes (allowed: at most " + std::to_string(kMaxGridNodes) +
                         " nodes: a larger cell)");
  }
  const DistanceGrid grid = distance_grid(m.mesh, m.closed, cell, margin);
  c.grid_origin = to_real(grid.origin);
  c.grid_cell = real(grid.cell);
  for (int a = 0; a < 3; ++a) c.grid_dims[a] = grid.dims[size_t(a)];
  c.grid_offset = int64_t(in.collider_grids.size());
  in.collider_grids.insert(in.collider_grids.end(), grid.distance.begin(), grid.distance.end());
  const Box3d box = bounds(m.mesh);
  c.size = to_real(0.5 * box.size());
  // Probes: the vertices, every n-th so there are at most kMeshProbes.
  std::vector<Vec3> probes;
  const size_t stride = (m.mesh.vertices.size() + kMeshProbes - 1) / kMeshProbes;
  for (size_t v = 0; v < m.mesh.vertices.size(); v += std::max<size_t>(stride, 1))
    probes.push_back(to_real(m.mesh.vertices[v]));
  in.collider_probes.back() = std::move(probes);
  meshes.back() = std::move(m.mesh);
}

// The radius about the centre that holds the whole shape (0 for an unbounded plane).
double bounding_radius(const Collider& c, const TriMesh& mesh) {
  const double x = double(c.size.x), y = double(c.size.y), z = double(c.size.z);
  switch (c.shape) {
    case kColliderSphere:
      return x;
    case kColliderBox:
      return std::sqrt(x * x + y * y + z * z);
    case kColliderCapsule:
      return x + y;
    case kColliderCylinder:
      return std::sqrt(x * x + y * y);
    case kColliderMesh: {
      double r = 0;
      for (const Vec3d& v : mesh.vertices) r = std::max(r, norm(v));
      return r;
    }
    default:
      return 0;
  }
}

// The fastest a point of a collider's surface moves: its centre's speed (the fastest segment of a
// path; a free body's initial speed) plus its turn times its bounding radius.
double top_speed(const Collider& c, const ColliderScript& s) {
  double centre = norm(s.velocity);
  for (size_t k = 1; k < s.path.size(); ++k) {
    const Keyframe &a = s.path[k - 1], &b = s.path[k];
    const double d = std::sqrt((b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]) +
                               (b[3] - a[3]) * (b[3] - a[3]));
    if (b[0] > a[0]) centre = std::max(centre, d / (b[0] - a[0]));
  }
  return centre + norm(s.omega) * double(c.bound);
}

}  // namespace

// The rotation (row major, shape frame to world) that turns the shape's y axis onto `axis`.
std::array<double, 9> rotation_onto(const Vec3d& axis) {
  const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  const double a[3] = {axis[0] / len, axis[1] / len, axis[2] / len};
  if (a[1] < -1 + 1e-12) return {1, 0, 0, 0, -1, 0, 0, 0, -1};  // half a turn about x
  // Rodrigues about y x a, by the angle between them: R = I + K + K^2 / (1 + cos).
  const double v[3] = {a[2], 0, -a[0]}, c = a[1];
  const double k[9] = {0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0};
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double k2 = 0;
      for (int q = 0; q < 3; ++q) k2 += k[3 * i + q] * k[3 * q + j];
      r[size_t(3 * i + j)] += k[3 * i + j] + k2 / (1 + c);
    }
  return r;
}

// Young's modulus of a material (bond-based: Poisson's ratio 1/4).
double youngs_modulus(const SceneMaterial& m) {
  if (m.shear_modulus > 0)
    return 9 * m.bulk_modulus * m.shear_modulus / (3 * m.bulk_modulus + m.shear_modulus);
  return 1.5 * m.bulk_modulus;
}

std::vector<TriMesh> add_colliders(const Scene& scene, SimulationInput& in) {
  double stiffest = 0;
  for (const SceneMaterial& m : scene.materials) stiffest = std::max(stiffest, youngs_modulus(m));
  std::vector<TriMesh> meshes;
  in.collider_probes.resize(in.colliders.size());
  for (size_t k = 0; k < scene.colliders.size(); ++k) {
    const SceneCollider& sc = scene.colliders[k];
    Collider c;
    c.shape = sc.shape == "sphere"     ? kColliderSphere
              : sc.shape == "box"      ? kColliderBox
              : sc.shape == "capsule"  ? kColliderCapsule
              : sc.shape == "cylinder" ? kColliderCylinder
              : sc.shape == "mesh"     ? kColliderMesh
                                       : kColliderPlane;
    if (sc.shape == "box")
      c.size = to_real({0.5 * sc.size[0], 0.5 * sc.size[1], 0.5 * sc.size[2]});
    else
      c.size = to_real({sc.radius, 0.5 * sc.length, 0});
    c.stiffness = real(sc.stiffness.value_or(stiffest));
    c.friction_dynamic = real(sc.friction);
    c.friction_static = real(sc.static_friction.value_or(sc.friction));
    c.damping = real(sc.damping);
    c.law = sc.law == "lammps_indent" ? kLawLammpsIndent : kLawPenalty;
    ColliderScript script;
    script.center = sc.center;
    script.rotation = rotation_onto(sc.axis);
    script.velocity = sc.velocity;
    for (const SceneKeyframe& key : sc.path) script.path.push_back(key);
    script.omega = sc.angular_velocity;
    meshes.emplace_back();
    in.collider_probes.emplace_back();
    if (c.shape == kColliderMesh)
      add_mesh_collider(sc, "colliders[" + std::to_string(k) + "]", scene, in, c, script, meshes);
    else if (sc.mass || sc.density)
      set_mass_and_inertia(sc, script);
    c.bound = real(bounding_radius(c, meshes.back()));
    in.colliders.push_back(c);
    in.motion.colliders.push_back(script);
  }
  return meshes;
}

double colliders_critical_dt(const SimulationInput& in, const std::vector<double>& material_dt) {
  double dt = std::numeric_limits<double>::infinity();
  double stiffness = 0;
  for (const Collider& c : in.colliders)  // (the indent law's stiffness grows with the depth: not here)
    if (c.law == kLawPenalty) stiffness = std::max(stiffness, double(c.stiffness));
  const ParticleSet& ps = in.particles;
  if (stiffness > 0)
    for (size_t i = 0; i < ps.size(); ++i) {
      const double m_dt = material_dt[size_t(ps.material[i])];
      const double rate = stiffness * std::cbrt(double(ps.volume[i])) / double(ps.mass[i]);
      dt = std::fmin(dt, std::sqrt(2.0 / (2.0 / (m_dt * m_dt) + rate)));
    }
  // A moving collider must not sweep through more than a quarter of the smallest particle in a
  // step, or a particle it meets is pressed deep at once and the push adds energy.
  double smallest = HUGE_VAL, fastest = 0;
  for (real v : ps.volume) smallest = std::min(smallest, std::cbrt(double(v)));
  for (size_t k = 0; k < in.colliders.size(); ++k)
    if (in.colliders[k].law == kLawPenalty)
      fastest = std::max(fastest, top_speed(in.colliders[k], in.motion.colliders[k]));
  if (fastest > 0 && smallest < HUGE_VAL) dt = std::fmin(dt, 0.25 * smallest / fastest);
  // Free colliders touching each other (body_contact.h): the stiffest such contact's step.
  std::vector<double> masses;
  for (const ColliderScript& s : in.motion.colliders) masses.push_back(s.free() ? s.mass : 0.0);
  const double body_rate =
      body_contact_rate(in.colliders, masses, {in.collider_grids.data(), &in.collider_probes});
  if (body_rate > 0) dt = std::fmin(dt, std::sqrt(2.0) / body_rate);
  return dt;
}

// One line on stderr per collider that starts with particles' centres inside it: they would be
// thrown out at once (a scene smell, not an error: a press may start closed on purpose).
int64_t warn_of_particles_inside_colliders(const SimulationInput& in,
                                           const std::vector<std::string>& body_names) {
  int64_t warned = 0;
  std::vector<Collider> posed = in.colliders;
  in.motion.pose_colliders(0, posed);
  FreeBodies(in.motion.colliders).pose(posed);
  for (size_t k = 0; k < posed.size(); ++k) {
    if (posed[k].law != kLawPenalty) continue;
    std::vector<int64_t> inside(body_names.size(), 0), pressed(body_names.size(), 0);
    std::vector<double> deepest(body_names.size(), 0);
    for (size_t i = 0; i < in.particles.size(); ++i) {
      const double distance =
          collider_surface(posed[k], in.particles.rest[i], in.collider_grids.data()).distance;
      const double depth = 0.5 * std::cbrt(double(in.particles.volume[i])) - distance;
      const size_t b = size_t(in.particles.body[i]);
      if (distance < 0) ++inside[b];
      if (depth > 1e-4 * (depth + distance) && distance >= 0) {  // (not a round-off's touch)
        ++pressed[b];
        deepest[b] = std::max(deepest[b], depth);
      }
    }
    for (size_t b = 0; b < inside.size(); ++b) {
      if (inside[b] > 0)
        std::fprintf(
            stderr,
            "warning: colliders[%zu]: %lld particles of body '%s' start inside it and will be thrown "
            "out at once (move it clear of the body, or mean it)\n",
            k, (long long)inside[b], body_names[b].c_str());
      // Within their contact radius V^(1/3) / 2 (a box grid's spacing along one axis can be a
      // little less): pushed from the first step, which breaks a brittle body's bonds.
      if (pressed[b] > 0)
        std::fprintf(stderr,
                     "warning: colliders[%zu]: %lld particles of body '%s' start pressed up to %.3g m into "
                     "it (within their contact radius V^(1/3)/2): it pushes them from the first step, "
                     "which cracks a brittle body; move the body %.3g m or more away from it\n",
                     k, (long long)pressed[b], body_names[b].c_str(), deepest[b], deepest[b]);
      warned += inside[b] + pressed[b];
    }
  }
  return warned;
}

MassProperties mass_properties(const TriMesh& mesh) {
  MassProperties m;
  double second[9] = {};  // the integral of x x^T over the solid, about the origin
  Vec3d first{0, 0, 0};
  for (const Triangle& t : mesh.triangles) {
    const Vec3d& a = mesh.vertices[size_t(t[0])];
    const Vec3d& b = mesh.vertices[size_t(t[1])];
    const Vec3d& c = mesh.vertices[size_t(t[2])];
    const double v = dot(a, cross(b, c)) / 6;  // the tetrahedron (0, a, b, c)
    m.volume += v;
    const Vec3d s = a + b + c;
    first = first + (v / 4) * s;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        second[3 * i + j] += v / 20 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
  }
  m.centroid = (1 / m.volume) * first;
  // About the centroid, and I = tr(C) Id - C.
  double c[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[3 * i + j] = second[3 * i + j] - m.volume * m.centroid[i] * m.centroid[j];
  const double trace = c[0] + c[4] + c[8];
  for (int i = 0; i < 9; ++i) m.inertia[size_t(i)] = (i % 4 == 0 ? trace : 0) - c[i];
  return m;
}

}  // namespace pd
