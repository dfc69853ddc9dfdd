// Tetrahedral particles (Levine sec. 4 "mesh-based geometry"; Chen sec. 5.2): one particle
// per tet at its barycentre with the tet's volume, tets sharing a face adjacent. Also
// Levine's fattened shell for thin objects: layers inward from a surface, tets between them.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/geometry/particle_geometry.h"
#include "host/geometry/tetgen.h"

namespace pd {

// Particles of an existing tet mesh (kept in the result, its tets reordered along a space-filling
// curve: curve_order.h). A flat tet (no volume) shares its largest face neighbour's volume.
ParticleGeometry tet_particles(TetMesh mesh);

// The most particles a body may have: a number, or one found where first asked for (a run finds
// its budget, the GPU's free memory, which starts its driver, on a thread of its own while
// TetGen runs).
class ParticleLimit {
 public:
  ParticleLimit(int64_t count) : find_([count] { return count; }) {}  // NOLINT: a count is a limit
  explicit ParticleLimit(std::function<int64_t()> find) : find_(std::move(find)) {}
  int64_t operator()() const { return find_(); }

 private:
  std::function<int64_t()> find_;
};

// TetGen on the closed solid, then tet_particles. MeshError naming `name` when the volume bound
// allows more than max_particles tets (checked once TetGen has started, which it stops), or
// TetGen made more.
ParticleGeometry tet_particles(const TriMesh& solid, const TetgenOptions& options,
                               const ParticleLimit& max_particles, const std::string& name);

// The solid between a surface and its copy moved `thickness` inward along the vertex normals
// (lengthened at creases so the depth holds from every adjacent face),
// closed along the boundary loops of an open surface (a sheet), and the vertices of
// `layers` - 2 evenly spaced layers between the two, which TetGen inserts as tet corners.
// A thickness at or past `limit` folds the inner surface over: some triangle of it turns over
// (its corners moved past one another), where the solid is thinner than the shell. Thrown by
// fattened_shell; the message names the place and the limit.
class ShellThicknessError : public std::invalid_argument {
 public:
  ShellThicknessError(double thickness, double limit, const Vec3d& where);
  double limit;
};
struct FattenedShell {
  TriMesh solid;
  std::vector<Vec3d> layer_points;
};
FattenedShell fattened_shell(const TriMesh& surface, double thickness, int layers);

// The vertex layers of a shell when its spacing is multiplied by `spacing_factor` (--scale):
// the thickness is geometry and stays, so the gaps between layers (layers - 1) follow
// thickness / spacing: round((layers - 1) / spacing_factor), at least one (two layers, the outer
// and the inner surface).
int scaled_shell_layers(int layers, double spacing_factor);

// Tets of the fattened shell of `surface` (an open sheet such as vase_sheet(), or a closed mesh).
ParticleGeometry shell_particles(const TriMesh& surface, double thickness, int layers, TetgenOptions options,
                                 const ParticleLimit& max_particles, const std::string& name);

}  // namespace pd
