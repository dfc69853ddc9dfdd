// Cracks and regions of a scene: the triangles each crack shape makes, reproducible random walks,
// and per-particle strain limits from regions, through setup_scene.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "cuda/engine/bond_cuts.h"
#include "host/scene/scene_cracks.h"
#include "host/scene/scene_setup.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

const std::string kPlate = R"(
[simulation]
seed = 5
[materials.glass]
density = 2440
bulk_modulus = 4e10
strain_limit = 1e-3
strain_limit_scatter = 0
[[bodies]]
name = "plate"
size = [0.02, 0.01, 0.002]
spacing = 0.001
material = "glass"
)";

TEST(SceneCracks, EachShapeMakesItsTriangles) {
  const Scene s = parse_scene(kPlate + R"(
[[cracks]]
corners = [[0, -1, -1], [0, 1, -1], [0, 1, 1], [0, -1, 1]]
[[cracks]]
shape = "path"
points = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]
extrude = [0, 0, 0.01]
strength = 0.5
body = "plate"
[[cracks]]
shape = "random_walk"
start = [0, 0, 0]
extrude = [0, 0, 0.004]
walks = 5
steps = 7
step_length = 0.001
)",
                              "cracks.toml");
  const auto tris = crack_triangles(s);
  ASSERT_EQ(tris.size(), 2u + 4u + 5u * 7u * 2u);
  EXPECT_EQ(tris[0].strength, 0);
  EXPECT_EQ(tris[0].body, -1);
  EXPECT_EQ(tris[2].strength, 0.5);
  EXPECT_EQ(tris[2].body, 0);
  // The path's ribbon spans z in [-0.005, 0.005] along the polyline.
  EXPECT_EQ(tris[2].corner[0][2], -0.005);
  EXPECT_EQ(tris[2].corner[2][2], 0.005);
  // A quad's two triangles cover it: a segment through its centre crosses exactly one.
  int crossed = 0;
  for (int t = 0; t < 2; ++t)
    crossed += segment_crosses_triangle({-1, 0.3, 0.2}, {1, 0.3, 0.2}, tris[size_t(t)]);
  EXPECT_EQ(crossed, 1);
}

TEST(SceneCracks, RandomWalksAreReproducibleStepsLongAndInTheirPlane) {
  SceneCrack c;
  c.shape = "random_walk";
  c.start = {1, 2, 3};
  c.extrude = {0, 0, 1};
  c.walks = 4;
  c.steps = 50;
  c.step_length = 0.01;
  const auto a = random_walks(c, 9), b = random_walks(c, 9), other = random_walks(c, 10);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, other);
  for (const auto& line : a) {
    ASSERT_EQ(line.size(), 51u);
    for (size_t k = 1; k < line.size(); ++k) {
      EXPECT_NEAR(std::sqrt(distance2(line[k], line[k - 1])), 0.01, 1e-15);
      EXPECT_EQ(line[k][2], 3);  // in the plane normal to extrude
    }
  }
  // The walks leave in evenly spread directions: one per quarter turn.
  std::vector<int> quadrant(4, 0);
  for (const auto& line : a) {
    const double angle = std::atan2(line[1][1] - 2, line[1][0] - 1) + 0.25 * M_PI;
    ++quadrant[size_t(int(std::floor((angle + 2 * M_PI) / (0.5 * M_PI))) % 4)];
  }
  for (int q : quadrant) EXPECT_LE(q, 2);
}

// A region halves the strain limit of the particles inside; another sets it outright.
TEST(SceneCracks, RegionsSetStrainLimits) {
  const Scene s = parse_scene(kPlate + R"(
[[regions]]
box_min = [-1, -1, -1]
box_max = [0, 1, 1]
strain_limit_factor = 0.5
[[regions]]
shape = "sphere"
center = [0.009, 0, 0]
radius = 0.0011
strain_limit = 4e-3
)",
                              "regions.toml");
  const SetupResult r = setup_scene(s, {});
  const ParticleSet& ps = r.input.particles;
  int halved = 0, set = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Vec3 x = ps.rest[i];
    const bool in_sphere = std::pow(x.x - 0.009, 2) + x.y * x.y + x.z * x.z <= 0.0011 * 0.0011;
    const double expected = (in_sphere ? 4e-3 : 1e-3) * (x.x <= 0 ? 0.5 : 1);
    EXPECT_FLOAT_EQ(ps.strain_limit0[i], real(expected)) << i;
    halved += x.x <= 0;
    set += in_sphere;
  }
  EXPECT_GT(halved, 0);
  EXPECT_GT(set, 0);
}

class SceneCrackFiles : public testing::TempDirTest {};

// A crack mesh file is read, scaled and moved; a region mesh must be closed.
TEST_F(SceneCrackFiles, MeshCracksAndRegions) {
  std::ofstream(path("sheet.obj")) << "v 0 -1 -1\nv 0 1 -1\nv 0 1 1\nv 0 -1 1\nf 1 2 3\nf 1 3 4\n";
  const std::string scene = path("s.toml");
  const Scene s = parse_scene(kPlate + R"(
[[cracks]]
shape = "mesh"
mesh = "sheet.obj"
scale = 0.01
translate = [0.0005, 0, 0]
)",
                              scene);
  const auto tris = crack_triangles(s);
  ASSERT_EQ(tris.size(), 2u);
  EXPECT_DOUBLE_EQ(tris[0].corner[0][0], 0.0005);
  EXPECT_DOUBLE_EQ(tris[0].corner[1][1], 0.01);
  const Scene open = parse_scene(
      kPlate + "[[regions]]\nshape = \"mesh\"\nmesh = \"sheet.obj\"\nstrain_limit_factor = 2\n", scene);
  try {
    region_tests(open);
    FAIL() << "an open region mesh was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("regions[0].mesh"), std::string::npos) << e.what();
  }
}

// Through the whole set-up: a quad across the plate removes every bond crossing it.
TEST(SceneCracks, PreCrackedPlateLosesTheBondsAcross) {
  const Scene s = parse_scene(kPlate + R"(
[[cracks]]
corners = [[0, -1, -1], [0, 1, -1], [0, 1, 1], [0, -1, 1]]
)",
                              "cut.toml");
  const SetupResult r = setup_scene(s, {});
  auto e = make_cpu_engine(r.input);
  BondLists b;
  e->read_bonds(b);
  const BondsView v = b.view();
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
      EXPECT_EQ(r.input.particles.rest[size_t(i)].x < 0, r.input.particles.rest[size_t(j)].x < 0);
    }
  EXPECT_GT(e->family_stats().cuts.removed, 0);
  // The element faces on the cut are no longer adjacent: fragments and crack meshes see the crack.
  const ElementAdjacency& adj = r.adjacency;
  int64_t pairs = 0;
  for (size_t i = 0; i < adj.size(); ++i)
    for (int64_t k = adj.offset[i]; k < adj.offset[i + 1]; ++k) {
      const int32_t j = adj.neighbor[size_t(k)];
      EXPECT_EQ(r.input.particles.rest[i].x < 0, r.input.particles.rest[size_t(j)].x < 0) << i << "-" << j;
      ++pairs;
    }
  EXPECT_GT(pairs, 0);
}

}  // namespace
}  // namespace pd
