#include "host/fragments/particle_elements.h"

#include <utility>

#include "host/fragments/cube_complex.h"

namespace pd {

ElementComplex particle_elements(const std::vector<Vec3>& rest, const std::vector<real>& spacing,
                                 const ElementAdjacency& adjacency, const EmbeddedTets& tets,
                                 const std::vector<VoronoiElements>& voronoi, VoronoiComplexReport* report) {
  // Tets and Voronoi cells claim their particles; the rest are cubes.
  std::vector<ElementComplex> parts;
  std::vector<uint8_t> claimed(rest.size(), 0);
  if (!tets.empty()) parts.push_back(tet_complex(tets));
  for (const VoronoiElements& v : voronoi) {
    VoronoiComplexReport r;
    parts.push_back(voronoi_complex(*v.geometry, v.first_particle, &r));
    if (report) {
      report->boundary_cells += r.boundary_cells;
      report->failed_faces += r.failed_faces;
    }
  }
  for (const ElementComplex& part : parts)
    for (int32_t p : part.particle)
      if (p >= 0 && size_t(p) < claimed.size()) claimed[size_t(p)] = 1;
  std::vector<int32_t> cubes;
  for (size_t p = 0; p < rest.size(); ++p)
    if (!claimed[p]) cubes.push_back(int32_t(p));
  if (!cubes.empty()) parts.push_back(cube_complex(adjacency, rest, spacing, cubes));
  return assemble(rest.size(), std::move(parts));
}

}  // namespace pd
