// Particles made from a solid, with the geometric elements they stand for (Levine sec. 4):
// cubes of a regular grid, tetrahedra, or clipped Voronoi cells. The adjacency of elements
// (shared cube faces, tet faces, Voronoi faces) is what the fragment stage walks.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/element_adjacency.h"
#include "host/geometry/stage_time.h"
#include "host/geometry/tet_mesh.h"
#include "host/geometry/vec3d.h"
#include "host/geometry/voronoi_cells.h"

namespace pd {

enum class ElementKind { cube, tet, voronoi };

struct ParticleGeometry {
  ElementKind kind = ElementKind::cube;
  std::vector<Vec3d> position;    // rest position: cube centre, tet barycentre, Voronoi site [m]
  std::vector<double> volume;     // the element's volume (inside the solid) [m^3]
  std::vector<double> mass;       // density * volume [kg], see set_density
  std::vector<double> lambda;     // distance to the nearest other particle [m]
  double min_distance = 0;        // Levine's lambda: the smallest of `lambda` [m]
  ElementAdjacency adjacency;     // elements sharing a face
  double cube_side = 0;           // cubes: their edge length [m]
  TetMesh tets;                   // tets: the tet mesh, one particle per tet in the same order
  VoronoiCells cells;             // voronoi: the clipped cells and their surface triangles
  std::vector<StageTime> stages;  // wall time of each stage of the build, in order

  size_t size() const { return position.size(); }
  double total_volume() const;
};

// lambda and min_distance from the positions (a uniform-grid nearest-neighbour search).
void compute_lambda(ParticleGeometry& g);

// The median of `lambda`: the typical spacing of scattered particles, which their horizon is
// measured in (Levine's lambda for tets and Voronoi cells).
double median_nearest_distance(const ParticleGeometry& g);

// mass = density * volume.
void set_density(ParticleGeometry& g, double density);

}  // namespace pd
