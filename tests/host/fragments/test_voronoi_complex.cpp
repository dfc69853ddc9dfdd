// Voronoi cells cut to an object as elements: each encloses its particle's volume, the faces two
// cells share have the same area from both sides, and the faces on the surface add up to the
// object's surface.
#include "host/fragments/voronoi_complex.h"

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>

#include "host/geometry/grid_particles.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"

namespace pd {
namespace {

double face_area(const ElementComplex& c, int64_t f) {
  const int64_t b = c.face_corner_start[size_t(f)], end = c.face_corner_start[size_t(f) + 1];
  auto at = [&](int64_t k) { return c.vertices[size_t(c.corner_vertex[size_t(c.face_corner[size_t(k)])])]; };
  Vec3d sum{0, 0, 0};
  for (int64_t k = b + 1; k + 1 < end; ++k) sum = sum + cross(at(k) - at(b), at(k + 1) - at(b));
  return 0.5 * norm(sum);
}

// Areas are sums over the same points from both sides; volumes are exact for the polyhedral
// object, computed here and in the geometry stage by different formulas: they agree to round-off
// (at most 4e-14 relative seen), checked to 1e-11.
TEST(VoronoiComplex, CellsHoldTheirVolumeShareFacesAndCoverTheSurface) {
  for (const bool torus : {false, true}) {
    SCOPED_TRACE(torus ? "torus" : "box");
    const TriMesh solid = torus ? torus_mesh(0.03, 0.012, 0.004) : box_mesh({0.03, 0.02, 0.01});
    const ParticleGeometry g = voronoi_particles(solid, 0.003, 5, 100000, "solid");
    VoronoiComplexReport report;
    const ElementComplex c = voronoi_complex(g, 7, &report);
    check(c, g.size() + 7);
    EXPECT_EQ(report.failed_faces, 0u);
    std::map<std::pair<int32_t, int32_t>, double> shared;
    double surface = 0;
    for (size_t e = 0; e < c.size(); ++e) {
      EXPECT_EQ(c.particle[e], int32_t(e) + 7);
      EXPECT_NEAR(element_volume(c, e), g.volume[e], 1e-11 * g.volume[e]);
      for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f) {
        const int32_t o = c.face_other[size_t(f)];
        if (o < 0)
          surface += face_area(c, f);
        else
          shared[{int32_t(e) + 7, o}] += face_area(c, f);
      }
    }
    EXPECT_NEAR(surface, surface_area(solid), 1e-11 * surface_area(solid));
    for (const auto& [pair, a] : shared) {
      const auto back = shared.find({pair.second, pair.first});
      ASSERT_NE(back, shared.end()) << pair.first << "-" << pair.second;
      EXPECT_NEAR(a, back->second, 1e-11 * a);
    }
  }
  EXPECT_THROW(voronoi_complex(grid_particles(box_mesh({0.01, 0.01, 0.01}), 0.005, 100, "box")),
               std::invalid_argument);
}

}  // namespace
}  // namespace pd
