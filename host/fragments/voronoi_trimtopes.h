// Trimtopes of Voronoi particles (Levine sec. 5, Fig. 4), built once in rest space from the
// geometry stage's clipped cells and placed per frame by a rigid transform (a fragment's
// Procrustes fit). Kept in double: the face plane two neighbouring cells share is stored as
// exact negatives in both, and a rigid transform keeps it so, so touching trimtopes meet
// without cracks in float too.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "host/geometry/particle_geometry.h"
#include "render/primitive_set.h"

namespace pd {

struct RestTrimtopes {
  std::vector<int32_t> particle;        // the particle each cell belongs to (index in the run)
  std::vector<Vec3d> site;              // Voronoi site of each cell (its particle's rest position)
  std::vector<int64_t> plane_start{0};  // CSR: planes of cell i
  std::vector<Vec3d> plane_normal;      // outward unit normals
  std::vector<double> plane_offset;     // inside: dot(normal, x) <= offset
  std::vector<int64_t> tri_start{0};    // CSR: surface triangles of cell i
  std::vector<Vec3d> tri_vertex;        // 3 per triangle, outward orientation
  std::vector<Box3d> box;               // bounds of the cell's solid part

  size_t size() const { return site.size(); }
};

// The trimtopes of a Voronoi particle geometry (ElementKind::voronoi), one per particle in its
// order, their particles numbered from `first_particle`. Throws std::invalid_argument for another
// kind or cells that do not match the particles.
RestTrimtopes rest_trimtopes(const ParticleGeometry& g, int32_t first_particle = 0);

// Appends `more` to `all` (several Voronoi bodies in one run).
void append(RestTrimtopes& all, const RestTrimtopes& more);

// Appends trimtope i moved by x -> rotation x + translation; returns the primitive's index.
int32_t add_placed_trimtope(PrimitiveSet* prims, const RestTrimtopes& rest, size_t i,
                            const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);

}  // namespace pd
