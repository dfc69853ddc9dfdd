#include "host/geometry/grid_particles.h"

#include <cmath>
#include <cstdio>

#include "host/geometry/box_grid.h"
#include "host/geometry/inside_test.h"

namespace pd {

namespace {

// Particles of the occupied cells of an nx x ny x nz grid (`id` = particle or -1), with the
// face pairs between occupied neighbours.
void grid_adjacency(ParticleGeometry& g, const std::vector<int32_t>& id, const int64_t n[3]) {
  std::vector<std::pair<int32_t, int32_t>> pairs;
  pairs.reserve(3 * g.size());
  auto at = [&](int64_t i, int64_t j, int64_t k) { return id[size_t((k * n[1] + j) * n[0] + i)]; };
  for (int64_t k = 0; k < n[2]; ++k)
    for (int64_t j = 0; j < n[1]; ++j)
      for (int64_t i = 0; i < n[0]; ++i) {
        const int32_t a = at(i, j, k);
        if (a < 0) continue;
        if (i + 1 < n[0] && at(i + 1, j, k) >= 0) pairs.emplace_back(a, at(i + 1, j, k));
        if (j + 1 < n[1] && at(i, j + 1, k) >= 0) pairs.emplace_back(a, at(i, j + 1, k));
        if (k + 1 < n[2] && at(i, j, k + 1) >= 0) pairs.emplace_back(a, at(i, j, k + 1));
      }
  g.adjacency = adjacency_from_pairs(g.size(), std::move(pairs));
}

// The cubes' volumes, their grid-face adjacency (id: each grid cell's particle or -1) and spacing.
void finish_cubes(ParticleGeometry& g, double spacing, const std::vector<int32_t>& id, const int64_t n[3],
                  StageClock& clock) {
  g.volume.assign(g.size(), spacing * spacing * spacing);
  grid_adjacency(g, id, n);
  clock.lap("adjacency");
  compute_lambda(g);
  clock.lap("nearest distances");
}

}  // namespace

void check_particle_budget(double volume, double particle_volume, int64_t max_particles,
                           const std::string& name, const std::string& what) {
  const double estimate = volume / particle_volume;
  if (!(estimate <= double(max_particles))) {  // (not finite: counted as too many)
    char text[96];  // (%g: a mesh scaled by 1e20 has a volume of 60 digits and a count past int64)
    std::snprintf(text, sizeof text, "the solid (volume %.4g m^3) would need about %.4g particles at ",
                  volume, estimate);
    throw MeshError(name, text + what + " (allowed: at most " + std::to_string(max_particles) +
                              " particles per body; use a larger spacing or a smaller mesh scale)");
  }
}

ParticleGeometry grid_particles(const TriMesh& solid, double spacing, int64_t max_particles,
                                const std::string& name) {
  check_particle_budget(signed_volume(solid), spacing * spacing * spacing, max_particles, name,
                        "spacing " + std::to_string(spacing) + " m");
  const Box3d box = bounds(solid);
  const Vec3d center = box.center();
  int64_t n[3];
  double origin[3];
  // Cells of side `spacing` across the solid's box, as many as fit to the nearest (as the box
  // grid counts them), centred on it, a particle at each cell's centre: a box-like mesh gets the
  // box grid's layers, half a spacing in from its faces (points on the faces themselves went in
  // or out by the round-off of where the mesh was modelled).
  for (int a = 0; a < 3; ++a) {
    n[a] = std::max<int64_t>(1, std::llround(box.size()[a] / spacing));
    origin[a] = center[a] + (0.5 - 0.5 * double(n[a])) * spacing;
  }
  // One ray per (y, z) column: a centre is inside by the winding of the crossings beyond it.
  ParticleGeometry g;
  StageClock clock(&g.stages);
  const InsideTest inside(solid);
  std::vector<int32_t> id(size_t(n[0] * n[1] * n[2]), -1);
  g.kind = ElementKind::cube;
  g.cube_side = spacing;
  std::vector<InsideTest::Crossing> xs;
  for (int64_t k = 0; k < n[2]; ++k)
    for (int64_t j = 0; j < n[1]; ++j) {
      const double y = origin[1] + double(j) * spacing, z = origin[2] + double(k) * spacing;
      inside.crossings(y, z, xs);
      RowWalk row(xs);
      for (int64_t i = 0; i < n[0]; ++i) {
        const double x = origin[0] + double(i) * spacing;
        if (!row.inside(x)) continue;
        id[size_t((k * n[1] + j) * n[0] + i)] = int32_t(g.position.size());
        g.position.push_back({x, y, z});
      }
    }
  clock.lap("grid cells inside (ray per row)");
  // A solid much smaller than a cube of the spacing (a sphere less than a spacing across) would be
  // a particle of several times its volume, and mass: none, which the callers report as a body
  // holding no particle at this spacing.
  if (double(g.position.size()) * spacing * spacing * spacing > 2 * signed_volume(solid)) return {};
  finish_cubes(g, spacing, id, n, clock);
  return g;
}

ParticleGeometry lattice_particles(const Box3d& box, const Vec3d& origin, double spacing,
                                   const std::function<bool(const Vec3d&)>& inside, int64_t max_particles,
                                   const std::string& name) {
  // The lattice indices that reach the box, a millionth of a spacing of slack for round-off.
  int64_t first[3], n[3];
  for (int a = 0; a < 3; ++a) {
    first[a] = int64_t(std::ceil((box.lo[a] - origin[a]) / spacing - 1e-6));
    n[a] = std::max<int64_t>(0, int64_t(std::floor((box.hi[a] - origin[a]) / spacing + 1e-6)) - first[a] + 1);
  }
  ParticleGeometry g;
  StageClock clock(&g.stages);
  g.kind = ElementKind::cube;
  g.cube_side = spacing;
  std::vector<int32_t> id(size_t(n[0] * n[1] * n[2]), -1);
  for (int64_t k = 0; k < n[2]; ++k)
    for (int64_t j = 0; j < n[1]; ++j)
      for (int64_t i = 0; i < n[0]; ++i) {
        const Vec3d p{origin[0] + double(first[0] + i) * spacing, origin[1] + double(first[1] + j) * spacing,
                      origin[2] + double(first[2] + k) * spacing};
        if (!inside(p)) continue;
        if (int64_t(g.position.size()) >= max_particles)
          check_particle_budget(double(max_particles + 1) * spacing * spacing * spacing,
                                spacing * spacing * spacing, max_particles, name,
                                "spacing " + std::to_string(spacing) + " m");
        id[size_t((k * n[1] + j) * n[0] + i)] = int32_t(g.position.size());
        g.position.push_back(p);
      }
  clock.lap("lattice points inside");
  finish_cubes(g, spacing, id, n, clock);
  return g;
}

ParticleGeometry box_grid_particles(const Vec3d& center, const Vec3d& size, double spacing) {
  const auto counts = box_grid_counts(size, spacing);
  const int64_t n[3] = {counts[0], counts[1], counts[2]};
  ParticleGeometry g;
  g.kind = ElementKind::cube;
  g.cube_side = spacing;
  for (const Vec3& p : box_grid_points(center, size, spacing)) g.position.push_back({p.x, p.y, p.z});
  g.volume.assign(g.size(), spacing * spacing * spacing);
  std::vector<int32_t> id(g.size());
  for (size_t i = 0; i < id.size(); ++i) id[i] = int32_t(i);  // x fastest, then y, z
  grid_adjacency(g, id, n);
  // A full box grid's nearest neighbours are one spacing apart: no search (at 16.6M particles it
  // took about as long as the rest of the scene's set-up).
  if (g.size() < 2) {
    compute_lambda(g);
  } else {
    g.lambda.assign(g.size(), spacing);
    g.min_distance = spacing;
  }
  return g;
}

}  // namespace pd
