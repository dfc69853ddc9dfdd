// The elements of a Voronoi body (Levine sec. 4 "Voronoi-based geometry"): each particle's cell
// cut to the object, as the geometry stage made it (voronoi_particles.h). Its faces are the parts
// of its bisector faces inside the object, bordering the neighbour's cell, and the parts of the
// object's surface triangles inside the cell, on the surface. Each element's enclosed volume is its
// particle's volume.
//
// Every point is computed from what defines it, the same way in every cell that has it: a cell
// corner from its four sites, a crossing of a surface triangle with a cell edge from the three
// sites and the triangle, a crossing of a triangle edge with a face from the two vertices and the
// two sites. So cells that share a point share it bit for bit, and are joined by exact position.
#pragma once

#include <cstdint>

#include "host/fragments/element_complex.h"
#include "host/geometry/particle_geometry.h"

namespace pd {

struct VoronoiComplexReport {
  size_t boundary_cells = 0;  // cells the object's surface crosses
  size_t failed_faces = 0;    // faces whose part inside the object did not close into loops (skipped)
};

// Element k stands for particle first_particle + k. Throws std::invalid_argument for another
// element kind or cells that do not match the particles.
ElementComplex voronoi_complex(const ParticleGeometry& g, int32_t first_particle = 0,
                               VoronoiComplexReport* report = nullptr);

}  // namespace pd
