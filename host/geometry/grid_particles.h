// Regular-grid particles (Levine sec. 4): cubes of side `spacing` whose centres lie inside the
// solid, and grid-face adjacency (cubes sharing a face).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "host/geometry/particle_geometry.h"
#include "host/geometry/tri_mesh.h"

namespace pd {

// Cubes centred on the grid centre + (k + 1/2 - n/2) spacing per axis, n = ceil(extent/spacing) + 1,
// kept where the centre is inside `solid` (closed, outward; see check_solid). MeshError naming
// `name` when about volume / spacing^3 > max_particles.
ParticleGeometry grid_particles(const TriMesh& solid, double spacing, int64_t max_particles,
                                const std::string& name);

// Cubes of side `spacing` centred on the lattice points origin + spacing (i, j, k) within `box`
// for which `inside` holds (LAMMPS's `lattice sc` + `create_atoms` in a region), with grid-face
// adjacency. MeshError naming `name` when the box holds more than max_particles lattice points
// that are inside.
ParticleGeometry lattice_particles(const Box3d& box, const Vec3d& origin, double spacing,
                                   const std::function<bool(const Vec3d&)>& inside, int64_t max_particles,
                                   const std::string& name);

// The whole box of box_grid.h (round(size / spacing) cubes per axis), as a ParticleGeometry.
ParticleGeometry box_grid_particles(const Vec3d& center, const Vec3d& size, double spacing);

// MeshError when a solid of `volume` would need more than max_particles particles of volume
// `particle_volume` (the budget check of every particle kind).
void check_particle_budget(double volume, double particle_volume, int64_t max_particles,
                           const std::string& name, const std::string& what);

}  // namespace pd
