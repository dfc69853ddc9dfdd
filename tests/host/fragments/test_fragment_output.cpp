// The frame-loop object end to end on engine families: a block that is cut and whose right half
// turns away writes the expected components, transforms, points and piece surfaces.
#include "host/fragments/fragment_output.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/fragments/fragments_file.h"
#include "host/fragments/ply_points.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/host/fragments/mesh_checks.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

using FragmentOutputTest = testing::TempDirTest;

constexpr int kNx = 8, kNy = 4, kNz = 3;
constexpr double kLambda = 1e-3;

// Frame data with the right half (x index >= 4) turned by `angle` about z around (4, 0, 0) lambda.
FrameData frame(const SimulationInput& in, int64_t number, double angle) {
  FrameData f;
  f.frame = number;
  f.step = 100 * number;
  f.time = 1e-4 * double(number);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d pivot(4 * kLambda, 0, 0);
  for (size_t i = 0; i < in.particles.size(); ++i) {
    const Vec3 x = in.particles.rest[i];
    Eigen::Vector3d p(x.x, x.y, x.z);
    if (i % kNx >= 4) p = r * (p - pivot) + pivot;
    f.position.push_back({real(p.x()), real(p.y()), real(p.z())});
    f.velocity.push_back({0, 0, 0});
    f.damage.push_back(0);
    f.body.push_back(0);
  }
  return f;
}

// Breaks every bond between the halves, from both ends.
void cut(BondLists& bonds) {
  const BondsView v = bonds.view();
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
      if ((i % kNx < 4) != (j % kNx < 4)) bonds.neighbor[size_t(v.slot(i, k))] = ~j;
    }
}

TEST_F(FragmentOutputTest, CutBlockWritesTwoFragments) {
  const SimulationInput in = testing::lattice_block(kNx, kNy, kNz, kLambda);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  FragmentOutput out(in, bonds, {dir_.string(), 0, true});
  EXPECT_THROW(out.write_meshes(), std::logic_error);

  // Frame 0: one fragment at rest.
  FrameData f0 = frame(in, 0, 0);
  EXPECT_EQ(format_component_stats(out.process(f0, bonds)),
            "fragments 1 (64-127:1) singles 0.0% of the mass (free 0.0%)");
  EXPECT_EQ(f0.component, std::vector<int32_t>(f0.size(), 0));
  // The crack mesh (its adjacency derived from the families, in their order): nothing split.
  EXPECT_EQ(out.embedded_mesh().vertex_count(), out.embedded_mesh().original_vertex_count());
  EXPECT_EQ(out.crack_surface().crack_count(), 0u);

  // Frame 1: cut, right half turned by 0.3 rad.
  cut(bonds);
  FrameData f1 = frame(in, 1, 0.3);
  const ComponentStats split = out.process(f1, bonds);
  EXPECT_EQ(format_component_stats(split), "fragments 2 (32-63:2) singles 0.0% of the mass (free 0.0%)");
  EXPECT_EQ(split.singles, 0);
  EXPECT_NEAR(split.largest_mass / split.mass, 0.5, 1e-6);  // two equal halves
  for (size_t i = 0; i < f1.size(); ++i) EXPECT_EQ(f1.component[i], i % kNx < 4 ? 0 : 4);
  // The crack mesh: every cube face on the cut cracked and opened, two closed halves.
  EXPECT_EQ(out.embedded_mesh().crack_face_count(), size_t(kNy * kNz));
  EXPECT_EQ(out.embedded_mesh().open_crack_face_count(), size_t(kNy * kNz));
  EXPECT_EQ(read_crack_mesh(path(crack_mesh_file_name(1, "ply"))).crack_count(), size_t(2 * 2 * kNy * kNz));
  EXPECT_EQ(testing::closed_piece_volumes(out.crack_surface()).size(), 2u);

  // Files: the fragments and points of both frames, then the piece surfaces.
  const FragmentsFrame back = read_fragments_file(path(fragments_file_name(1)));
  EXPECT_EQ(back.step, 100);
  ASSERT_EQ(back.fragments.size(), 2u);
  EXPECT_EQ(back.fragments[0].id, 0);
  EXPECT_EQ(back.fragments[1].id, 4);
  EXPECT_LT((back.fragments[0].rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((back.fragments[1].rotation - Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-6);
  EXPECT_LT(back.fragments[1].fit.residual(), 1e-5);
  EXPECT_EQ(read_fragments_file(path(fragments_file_name(0))).fragments.size(), 1u);
  EXPECT_EQ(read_ply_points(path(points_file_name(1))).component, f1.component);
  EXPECT_TRUE(std::filesystem::exists(path(points_file_name(0))));
  out.write_meshes();
  std::ifstream obj(path("fragments.obj"));
  std::string line;
  std::vector<std::string> objects;
  while (std::getline(obj, line))
    if (line.rfind("o ", 0) == 0) objects.push_back(line);
  EXPECT_EQ(objects, (std::vector<std::string>{"o fragment_0", "o fragment_4"}));
}

TEST_F(FragmentOutputTest, BlendingStartsBothPiecesAtTheWholePose) {
  const SimulationInput in = testing::lattice_block(kNx, kNy, kNz, kLambda);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  FragmentOutput out(in, bonds, {dir_.string(), 3, false});
  FrameData f0 = frame(in, 0, 0);
  out.process(f0, bonds);
  cut(bonds);
  FrameData f1 = frame(in, 1, 0.3);
  out.process(f1, bonds);
  ASSERT_EQ(out.fragments().size(), 2u);
  const Fragment &a = out.fragments()[0], &b = out.fragments()[1];
  EXPECT_EQ(a.blend, 1);
  EXPECT_LT((a.rotation - b.rotation).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((a.translation - b.translation).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(std::filesystem::exists(path(points_file_name(1))));
  FrameData wrong = frame(in, 2, 0.3);
  wrong.position.pop_back();
  EXPECT_THROW(out.process(wrong, bonds), std::invalid_argument);
}

// A Voronoi body at rest: its particles sit closer than the nominal spacing, yet it neither
// collides with itself nor breaks, and the geometry's cell adjacency makes it one fragment, whose
// piece and crack mesh are the cells' outer surface.
TEST_F(FragmentOutputTest, VoronoiBodyAtRestIsOneFragment) {
  const Scene scene = parse_scene(R"(
[world]
gravity = [0.0, 0.0, 0.0]
[materials.stone]
density = 2400.0
bulk_modulus = 30e9
strain_limit = 5e-4
[[bodies]]
shape = "sphere"
radius = 0.02
particles = "voronoi"
spacing = 0.004
material = "stone"
)",
                                  "voronoi.toml");
  const SetupResult setup = setup_scene(scene, {});
  ASSERT_EQ(setup.voronoi.size(), 1u);
  ASSERT_EQ(setup.adjacency.size(), setup.input.particles.size());
  auto engine = make_cpu_engine(setup.input);
  engine->advance(200);
  EXPECT_EQ(engine->broken_bonds(), 0);
  BondLists bonds;
  engine->read_bonds(bonds);
  FragmentOutput out(setup.input, bonds, {dir_.string(), 0, false}, setup.adjacency, setup.embedded,
                     {{setup.voronoi[0].first_particle, &setup.voronoi[0].geometry}});
  FrameData f;
  f.position = setup.input.particles.rest;
  f.velocity.assign(f.position.size(), Vec3{0, 0, 0});
  f.damage.assign(f.position.size(), 0.0f);
  f.body = setup.input.particles.body;
  out.process(f, bonds);
  EXPECT_EQ(out.components().count(), 1u);
  out.write_meshes();
  std::ifstream obj(path("fragments.obj"));
  std::string line;
  size_t objects = 0;
  while (std::getline(obj, line)) objects += line.rfind("o ", 0) == 0;
  EXPECT_EQ(objects, 1u);
  const CrackSurface s = read_crack_mesh(path("crack_mesh_00000.ply"));
  EXPECT_EQ(s.crack_count(), 0u);
  EXPECT_EQ(testing::closed_piece_volumes(s).size(), 1u);
}

}  // namespace
}  // namespace pd
