// Contact between rigid colliders, so that a free body rests on the ground, rolls off a box or
// knocks a prop over. Computed on the host once per step for every pair with at least one free
// body (at most a few hundred colliders, a few dozen points each).
//
// One body of a pair gives probe points (a sphere its centre with its radius, a capsule points of
// its segment with its radius, a box its corners and edge midpoints, a cylinder points of its two
// rims) and the other its signed distance (colliders.h): a probe reaching d into the other is
// pushed out along the other's normal by the penalty k d, k = K L with K the smaller stiffness of
// the two [Pa] and L the probing shape's size (its radius, or a box's smallest half extent), less
// the damping 2 zeta sqrt(k m) of the approach (m the pair's reduced mass, zeta the larger damping
// ratio), never pulling; and Coulomb friction with the mean coefficients of the two, the static
// force being the one that stops the sliding within the step, shared by the pair's touching probes.
// Round shapes probe (a sphere before a capsule); two boxes, cylinders or meshes (their vertices,
// thinned to kMeshProbes) probe each other; a plane never probes, and two planes never touch. Edge-to-edge
// contact of two boxes between their probe points, and the part of a cylinder's side between its rims, are
// not seen. Colliders under the LAMMPS indent law push particles only.
#pragma once

#include <vector>

#include "cuda/kernels/colliders.h"

namespace pd {

// A point of a shape (in its frame) that touches with a ball of `radius` around it.
struct Probe {
  Vec3 point;
  real radius;
};

// What the analytic shapes do not say: the mesh colliders' distance grids and each mesh's probe
// points (its vertices, at most kMeshProbes of them, in its frame; empty for other shapes).
struct MeshShapes {
  const float* grids = nullptr;
  const std::vector<std::vector<Vec3>>* probes = nullptr;
};
constexpr size_t kMeshProbes = 256;

// The probe points of collider k's shape (none for a plane).
std::vector<Probe> shape_probes(const Collider& c, const MeshShapes& meshes = {}, size_t k = 0);

// The contact stiffness length L of a probing shape [m].
double probe_length(const Collider& c);

// The sum of the contact forces between colliders on each of them (force and torque about its
// centre), given the colliders at their current pose and velocities, each one's mass (0: not free,
// immovable by contact) and the step. Pairs of which neither is free are skipped.
std::vector<Wrench> body_contact_wrenches(const std::vector<Collider>& colliders,
                                          const std::vector<double>& masses, double dt,
                                          const MeshShapes& meshes = {});

// The largest rate sqrt(k_total / m) [1/s] of the body contacts a free collider can have (all its
// or the other's probes touching), for the stable step.
double body_contact_rate(const std::vector<Collider>& colliders, const std::vector<double>& masses,
                         const MeshShapes& meshes = {});

}  // namespace pd
