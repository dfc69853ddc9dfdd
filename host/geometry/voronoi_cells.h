// Clipped Voronoi cells of particles inside a solid, as the renderer and the fragment stage
// need them: each cell is the set of points nearer to its site than to any other site, cut to
// the solid. Its faces lie on the bisector planes of its site and the sites listed in
// `face_site`; an entry < 0 is a side of the cube of half-side `cube_half_side` around the site
// (-1 - (2 axis + (0 low, 1 high))), which only bounds parts outside the solid. Where the solid's
// surface crosses the cell, the surface triangles listed in `triangles` bound it (the trimtope
// of Levine Fig. 4): the cell's material is the part of its polytope behind those triangles.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

struct VoronoiCells {
  TriMesh surface;                          // the solid's surface, which the triangle ids refer to
  double cube_half_side = 0;                // each cell was first cut to this cube around its site [m]
  std::vector<int64_t> face_offset{0};      // CSR: faces of cell i are face_site[face_offset[i] ..]
  std::vector<int32_t> face_site;           // the other site of each bisector face, or a box side (< 0)
  std::vector<int64_t> triangle_offset{0};  // CSR: surface triangles crossing cell i
  std::vector<int32_t> triangles;
};

}  // namespace pd
