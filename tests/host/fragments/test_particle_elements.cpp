// A mixed scene's elements: grid cubes, Voronoi cells and (with TetGen) tets in one complex, one
// element per particle with its particle's volume; the whole scene's pieces are closed.
#include "host/fragments/particle_elements.h"

#include <gtest/gtest.h>

#include "host/fragments/adjacency.h"
#include "host/fragments/piece_mesh.h"
#include "host/geometry/tetgen.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "tests/host/fragments/mesh_checks.h"

namespace pd {
namespace {

TEST(ParticleElements, MixedSceneHasOneClosedElementPerParticle) {
  const bool tets = !find_tetgen().empty();
  std::string text = R"(
[materials.stone]
density = 2400
bulk_modulus = 3e10
strain_limit = 0.001
[[bodies]]
material = "stone"
size = [0.04, 0.02, 0.02]
spacing = 0.005
center = [0, -0.1, 0]
[[bodies]]
material = "stone"
shape = "sphere"
radius = 0.02
spacing = 0.005
particles = "voronoi"
)";
  if (tets)
    text +=
        "[[bodies]]\nmaterial = \"stone\"\nshape = \"sphere\"\nradius = 0.02\nspacing = 0.01\n"
        "particles = \"tets\"\ncenter = [0.1, 0, 0]\n";
  const SetupResult setup = setup_scene(parse_scene(text, "mixed.toml"), {});
  const ParticleSet& ps = setup.input.particles;
  std::vector<VoronoiElements> voronoi;
  for (const VoronoiBody& v : setup.voronoi) voronoi.push_back({v.first_particle, &v.geometry});
  const ElementComplex c = particle_elements(ps.rest, particle_spacing(ps, setup.input.materials),
                                             setup.adjacency, setup.embedded, voronoi);
  check(c, ps.size());
  ASSERT_EQ(c.size(), ps.size());
  // Float particle volumes and rest positions (cube corners): 1e-6 relative.
  for (size_t p = 0; p < ps.size(); ++p)
    EXPECT_NEAR(element_volume(c, p), ps.volume[p], 1e-6 * ps.volume[p]) << p;
  // One piece per body, each closed.
  const FragmentMesh m = fragment_pieces(c, components_from_ids(ps.body));
  ASSERT_EQ(m.objects(), tets ? 3u : 2u);
  for (size_t o = 0; o < m.objects(); ++o)
    testing::expect_closed(testing::object_polygons(m, o), false, "body " + std::to_string(o));
}

}  // namespace
}  // namespace pd
