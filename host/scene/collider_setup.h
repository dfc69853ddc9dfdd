// The scene's [[colliders]] made into the engine's colliders, their motion and, for mesh colliders,
// their distance grids and probe points; the stable step their push allows; and a warning for
// particles that start inside one.
#pragma once

#include <array>
#include <vector>

#include "cuda/engine/particle_set.h"
#include "host/geometry/tri_mesh.h"
#include "host/scene/scene.h"

namespace pd {

// The rotation (row major, shape frame to world) that turns the shape's y axis onto `axis`.
std::array<double, 9> rotation_onto(const Vec3d& axis);

// Young's modulus of a material (bond-based: Poisson's ratio 1/4), the colliders' default K.
double youngs_modulus(const SceneMaterial& m);

// Appends the colliders to `in` (after its particles, whose sizes set a mesh's default grid
// spacing and margin). Returns each collider's mesh in its frame (empty for analytic shapes).
// Throws MeshError for an unreadable or broken mesh file and SceneError for a free collider of an
// open mesh or a distance grid of too many nodes.
std::vector<TriMesh> add_colliders(const Scene& scene, SimulationInput& in);

// The stable step with the colliders' push on each particle (at its material's step
// `material_dt[material]`) and the free colliders' contacts with each other; infinity without.
double colliders_critical_dt(const SimulationInput& in, const std::vector<double>& material_dt);

// One line on stderr per collider that starts with particles' centres inside it, or pressed into
// it; returns how many particles start so.
int64_t warn_of_particles_inside_colliders(const SimulationInput& in,
                                           const std::vector<std::string>& body_names);

// Volume, centroid and inertia tensor (about the centroid, per unit density, row major) of a
// closed, outward mesh, from the signed tetrahedra of its triangles with the origin.
struct MassProperties {
  double volume = 0;
  Vec3d centroid{0, 0, 0};
  std::array<double, 9> inertia{};
};
MassProperties mass_properties(const TriMesh& mesh);

}  // namespace pd
