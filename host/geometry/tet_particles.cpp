#include "host/geometry/tet_particles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>

#include "host/geometry/curve_order.h"
#include "host/geometry/grid_particles.h"
#include "host/geometry/mesh_flips.h"
#include "host/geometry/particle_order.h"

namespace pd {

namespace {

// Tets of almost no volume (below this fraction of the mean): TetGen without its optimization
// pass (tetgen.cpp) leaves flat tets, four coplanar corners, where symmetric surface points
// meet, as along a box's edges.
constexpr double kFlatTetFraction = 1e-6;

// A flat tet's particle would have no mass (and NaN accelerations); each shares the volume of
// its largest face neighbour, half and half, so the body's volume and mass stay as they are.
void share_flat_tet_volumes(const TetMesh& mesh, std::vector<double>& volume) {
  double mean = 0;
  for (double v : volume) mean += v / double(volume.size());
  const double flat = kFlatTetFraction * mean;
  for (size_t t = 0; t < volume.size(); ++t) {
    if (volume[t] >= flat) continue;
    int32_t largest = -1;
    for (int32_t other : mesh.neighbors[t])
      if (other >= 0 && (largest < 0 || volume[size_t(other)] > volume[size_t(largest)])) largest = other;
    if (largest < 0) continue;  // (a lone tet: nothing to share)
    const double half = 0.5 * (volume[t] + volume[size_t(largest)]);
    volume[t] = half;
    volume[size_t(largest)] = half;
  }
}

// The particles' adjacency: each tet's face neighbours, sorted (the relation is symmetric, as
// the mesh's faces are shared by two tets or lie on its surface).
ElementAdjacency face_adjacency(const TetMesh& mesh) {
  const int64_t n = int64_t(mesh.tets.size());
  ElementAdjacency adj;
  adj.offset.assign(size_t(n) + 1, 0);
  for (int64_t t = 0; t < n; ++t) {
    int64_t count = 0;
    for (int32_t other : mesh.neighbors[size_t(t)]) count += other >= 0;
    adj.offset[size_t(t) + 1] = adj.offset[size_t(t)] + count;
  }
  adj.neighbor.resize(size_t(adj.offset[size_t(n)]));
#pragma omp parallel for schedule(static)
  for (int64_t t = 0; t < n; ++t) {
    int32_t* row = adj.neighbor.data() + adj.offset[size_t(t)];
    int32_t m = 0;
    for (int32_t other : mesh.neighbors[size_t(t)])
      if (other >= 0) row[m++] = other;
    std::sort(row, row + m);
  }
  return adj;
}

}  // namespace

ParticleGeometry tet_particles(TetMesh mesh) {
  ParticleGeometry g;
  StageClock clock(&g.stages);
  g.kind = ElementKind::tet;
  const int64_t n = int64_t(mesh.tets.size());
  g.position.resize(size_t(n));
  g.volume.resize(size_t(n));
#pragma omp parallel for schedule(static)
  for (int64_t t = 0; t < n; ++t) {
    g.position[size_t(t)] = mesh.barycenter(size_t(t));
    g.volume[size_t(t)] = mesh.volume(size_t(t));
  }
  share_flat_tet_volumes(mesh, g.volume);
  g.tets = std::move(mesh);
  // In curve order first, then the adjacency from the renumbered neighbours.
  reorder_particles(g, morton_order(g.position));
  g.adjacency = face_adjacency(g.tets);
  clock.lap("tet particles + adjacency, in curve order");
  compute_lambda(g);
  clock.lap("nearest distances");
  return g;
}

ParticleGeometry tet_particles(const TriMesh& solid, const TetgenOptions& options,
                               const ParticleLimit& max_particles, const std::string& name) {
  std::vector<StageTime> stages;
  TetgenOptions timed = options;
  if (!timed.stages) timed.stages = &stages;
  // The volume bound's count against the limit, beside TetGen (which it stops when over).
  timed.while_running = [&] {
    if (options.while_running) options.while_running();
    if (options.max_volume > 0) {
      char bound[64];
      std::snprintf(bound, sizeof bound, "tet volumes of at most %.3g m^3", options.max_volume);
      check_particle_budget(signed_volume(solid), options.max_volume, max_particles(), name, bound);
    }
  };
  TetMesh mesh = tetrahedralize(solid, timed, name);
  if (int64_t(mesh.tets.size()) > max_particles())
    throw MeshError(name, "TetGen made " + std::to_string(mesh.tets.size()) + " tets (allowed: at most " +
                              std::to_string(max_particles()) +
                              " particles per body; raise the volume bound)");
  ParticleGeometry g = tet_particles(std::move(mesh));
  if (timed.stages == &stages) g.stages.insert(g.stages.begin(), stages.begin(), stages.end());
  return g;
}

// Radians: a flip moves the surface by about half the bend times a triangle's height at most.
constexpr double kShellFlipDihedral = 0.25;

namespace {

// The depth at which triangle (a, b, c), its corners moved inward along their normals, first turns
// over: the least positive root of n(t) . n(0) = 0 with n(t) the normal of (a - t na, b - t nb,
// c - t nc), a quadratic in t; +infinity where it never does.
double fold_depth(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& na, const Vec3d& nb,
                  const Vec3d& nc) {
  const Vec3d e1 = b - a, e2 = c - a, d1 = nb - na, d2 = nc - na, n0 = cross(e1, e2);
  const double c0 = dot(n0, n0), c1 = -dot(cross(e1, d2) + cross(d1, e2), n0), c2 = dot(cross(d1, d2), n0);
  if (!(c0 > 0)) return INFINITY;  // a triangle without area has no side to turn over
  double least = INFINITY;
  if (std::abs(c2) <= 1e-12 * (std::abs(c1) + c0)) {
    if (c1 < 0) least = -c0 / c1;
  } else {
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc >= 0)
      for (const double root : {(-c1 - std::sqrt(disc)) / (2 * c2), (-c1 + std::sqrt(disc)) / (2 * c2)})
        if (root > 0) least = std::min(least, root);
  }
  return least;
}

}  // namespace

ShellThicknessError::ShellThicknessError(double thickness, double limit_, const Vec3d& where)
    : std::invalid_argument([&] {
        char text[320];
        std::snprintf(
            text, sizeof text,
            "a shell %.4g m thick folds its inner surface over near (%.4g, %.4g, %.4g): the solid is "
            "thinner than that there (allowed: below %.4g m for this surface)",
            thickness, where[0], where[1], where[2], limit_);
        return std::string(text);
      }()),
      limit(limit_) {}

FattenedShell fattened_shell(const TriMesh& surface, double thickness, int layers) {
  // Area-weighted vertex normals (outward for a closed, outward mesh), lengthened at creases
  // (mitred) so a layer keeps its depth from every adjacent face: n / min over faces of n . n_f,
  // capped at 3 for very sharp corners.
  const size_t nv = surface.vertices.size();
  std::vector<Vec3d> normal(nv, Vec3d{0, 0, 0});
  std::vector<Vec3d> face_normal(surface.triangles.size());
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    const Triangle& t = surface.triangles[f];
    const Vec3d n = cross(surface.vertices[t[1]] - surface.vertices[t[0]],
                          surface.vertices[t[2]] - surface.vertices[t[0]]);
    face_normal[f] = (1 / std::max(norm(n), 1e-300)) * n;
    for (int32_t v : t) normal[v] = normal[v] + n;
  }
  for (Vec3d& n : normal) n = (1 / std::max(norm(n), 1e-300)) * n;
  std::vector<double> mitre(nv, 1.0);
  for (size_t f = 0; f < surface.triangles.size(); ++f)
    for (int32_t v : surface.triangles[f])
      mitre[v] = std::max(mitre[v], 1 / std::max(dot(normal[v], face_normal[f]), 1.0 / 3));
  for (size_t v = 0; v < nv; ++v) normal[v] = mitre[v] * normal[v];
  // The inner surface must not turn over anywhere: a thickness past the solid's own there.
  double limit = INFINITY;
  size_t folds = 0;
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    const Triangle& t = surface.triangles[f];
    const double depth = fold_depth(surface.vertices[t[0]], surface.vertices[t[1]], surface.vertices[t[2]],
                                    normal[t[0]], normal[t[1]], normal[t[2]]);
    if (depth < limit) limit = depth, folds = f;
  }
  if (thickness >= limit) {
    const Triangle& t = surface.triangles[folds];
    throw ShellThicknessError(
        thickness, limit,
        (1.0 / 3) * (surface.vertices[t[0]] + surface.vertices[t[1]] + surface.vertices[t[2]]));
  }
  auto layer = [&](double depth) {
    std::vector<Vec3d> points(surface.vertices.size());
    for (size_t v = 0; v < points.size(); ++v) points[v] = surface.vertices[v] - depth * normal[v];
    return points;
  };

  // Outer surface, inner surface reversed, and a strip along each boundary edge a -> b of the
  // outer surface: triangles (b, a, a') and (b, a', b'), primes on the inner surface.
  FattenedShell shell;
  shell.solid = surface;
  const int32_t base = int32_t(surface.vertices.size());
  for (const Vec3d& p : layer(thickness)) shell.solid.vertices.push_back(p);
  for (const Triangle& t : surface.triangles)
    shell.solid.triangles.push_back({t[0] + base, t[2] + base, t[1] + base});
  std::unordered_map<uint64_t, int> uses;
  auto key = [](int32_t a, int32_t b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); };
  for (const Triangle& t : surface.triangles)
    for (int c = 0; c < 3; ++c) ++uses[key(std::min(t[c], t[(c + 1) % 3]), std::max(t[c], t[(c + 1) % 3]))];
  for (const Triangle& t : surface.triangles)
    for (int c = 0; c < 3; ++c) {
      const int32_t a = t[c], b = t[(c + 1) % 3];
      if (uses[key(std::min(a, b), std::max(a, b))] != 1) continue;
      shell.solid.triangles.push_back({b, a, a + base});
      shell.solid.triangles.push_back({b, a + base, b + base});
    }
  // Where two triangles bend by under kShellFlipDihedral, the edge is flipped toward Delaunay: the
  // inner surface, drawn in along the normals, holds many an edge with a corner inside its
  // diametral sphere, which TetGen would split (the vase at Levine's size: TetGen 16% faster,
  // bench/NOTES.md).
  delaunay_flips(shell.solid, kShellFlipDihedral);
  // Layers strictly between the outer and inner surfaces.
  for (int k = 1; k + 1 < layers; ++k)
    for (const Vec3d& p : layer(thickness * k / (layers - 1))) shell.layer_points.push_back(p);
  return shell;
}

int scaled_shell_layers(int layers, double spacing_factor) {
  const double gaps = double(std::max(layers, 2) - 1) / spacing_factor;
  return 1 + int(std::max(1.0, std::round(std::min(gaps, 1e6))));
}

ParticleGeometry shell_particles(const TriMesh& surface, double thickness, int layers, TetgenOptions options,
                                 const ParticleLimit& max_particles, const std::string& name) {
  FattenedShell shell = fattened_shell(surface, thickness, layers);
  options.extra_points = std::move(shell.layer_points);
  return tet_particles(shell.solid, options, max_particles, name);
}

}  // namespace pd
