// The crack mesh (host/fragments/crack_mesh_file.h) as raytracer triangles, for `perifrac render
// --surface mesh`: the bodies it covers drawn from their split surface instead of their elements,
// shaded smooth. Render-side only; the mesh files are not changed.
//
// Normals: per vertex, area-weighted over the triangles at the vertex, separately on the original
// surface and on the crack surfaces (a vertex on both gets one normal for each, so the edge where a
// crack meets the surface stays sharp); a triangle whose normal differs from another's by more
// than the crease angle takes no part in that one's vertex normal (a cube's edges stay sharp).
//
// Smoothing (Chen et al. note that element faces give a zig-zag crack surface): Taubin's
// lambda/mu passes (Taubin 1995, "A signal processing approach to fair surface design") over the
// crack-surface vertices that are not on the original surface; those stay where they are.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "host/fragments/crack_mesh_file.h"
#include "render/primitive_set.h"

namespace pd {

constexpr double kCreaseDegrees = 60;      // faces further apart than this keep their own normals
constexpr int kDefaultCrackSmoothing = 2;  // Taubin passes of --smooth-cracks
constexpr double kTaubinLambda = 0.5, kTaubinMu = -0.53;

// Per triangle, the unit shading normals at its three corners (the rules above).
std::vector<std::array<Vec3d, 3>> corner_normals(const CrackSurface& s,
                                                 double crease_degrees = kCreaseDegrees);

// Moves the vertices that only crack triangles use by `passes` Taubin passes (each a lambda step
// then a mu step towards the mean of the vertex's neighbours along crack-triangle edges).
void smooth_cracks(CrackSurface& s, int passes, double lambda = kTaubinLambda, double mu = kTaubinMu);

// One flag per particle: 1 for the particles of every body that owns a triangle of `s` (a body's
// elements are all in the mesh, those deep inside too, which own none). `body`: each particle's
// body. Throws std::invalid_argument when `s` has no owners (a file written before they were
// stored) or an owner is not a particle.
std::vector<uint8_t> covered_particles(const CrackSurface& s, const std::vector<int32_t>& body);

// Appends the triangles of `s` with `normals` (corner_normals) to `prims`, each with the albedo
// and material of its owning particle (`albedo` and `material` hold one entry per particle first;
// an empty `material` stays empty).
void add_surface_triangles(const CrackSurface& s, const std::vector<std::array<Vec3d, 3>>& normals,
                           PrimitiveSet* prims, std::vector<Vec3>* albedo, std::vector<uint8_t>* material);

}  // namespace pd
