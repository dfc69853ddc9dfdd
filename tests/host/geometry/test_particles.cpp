// Particles from solids: grid, tets (TetGen), Voronoi. Volume conservation, particles
// inside the solid, Poisson-disk distance, tiling, symmetric adjacency, TetGen barycentres.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "host/geometry/grid_particles.h"
#include "host/geometry/inside_test.h"
#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tet_body_solids.h"
#include "host/geometry/tet_particles.h"
#include "host/geometry/voronoi_particles.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

constexpr int64_t kBudget = 20'000'000;

void expect_symmetric(const ElementAdjacency& a) {
  for (size_t i = 0; i < a.size(); ++i)
    for (int64_t k = a.offset[i]; k < a.offset[i + 1]; ++k) {
      const int32_t j = a.neighbor[size_t(k)];
      ASSERT_NE(size_t(j), i);
      const auto* begin = a.neighbor.data() + a.offset[size_t(j)];
      const auto* end = a.neighbor.data() + a.offset[size_t(j) + 1];
      ASSERT_TRUE(std::binary_search(begin, end, int32_t(i))) << i << " -> " << j << " but not back";
    }
}

void expect_inside(const TriMesh& solid, const ParticleGeometry& g) {
  const InsideTest inside(solid);
  size_t outside = 0;
  for (const Vec3d& p : g.position) outside += !inside.inside(p);
  EXPECT_EQ(outside, 0u);
}

// The spot mesh of the shared folder, checked and scaled to about 1 m.
TriMesh spot_solid(const std::string& path) {
  TriMesh m = read_mesh(path);
  check_solid(m, path, {});
  return m;
}

bool have_tetgen() {
  return !find_tetgen().empty();
}

// ---- grid -------------------------------------------------------------------------------------

TEST(GridParticles, SphereVolumeAndAdjacency) {
  const double r = 1, h = 0.05;  // 20 cubes per radius
  const TriMesh sphere = sphere_mesh(r, 0.02);
  const ParticleGeometry g = grid_particles(sphere, h, kBudget, "sphere");
  // Counting cubes by their centres: the error is the surface's cut cells, mostly cancelling.
  EXPECT_NEAR(g.total_volume(), signed_volume(sphere), 0.01 * signed_volume(sphere));
  expect_inside(sphere, g);
  expect_symmetric(g.adjacency);
  EXPECT_NEAR(g.min_distance, h, 1e-12);
  for (double l : g.lambda) ASSERT_NEAR(l, h, 1e-12);
  // An interior cube has 6 face neighbours.
  size_t six = 0;
  for (size_t i = 0; i < g.size(); ++i) six += g.adjacency.degree(i) == 6;
  EXPECT_GT(six, g.size() * 8 / 10);
}

TEST(GridParticles, BoxGridKeepsTheBoxLayout) {
  const ParticleGeometry g = box_grid_particles({0, 0, 0}, {0.1, 0.05, 0.03}, 0.01);
  EXPECT_EQ(g.size(), 10u * 5 * 3);
  EXPECT_NEAR(g.total_volume(), 0.1 * 0.05 * 0.03, 1e-12);
  expect_symmetric(g.adjacency);
  EXPECT_EQ(g.adjacency.degree(0), 3);  // a corner cube
  // Nearest distances: the spacing, as the search over the positions finds it (to their round-off).
  ParticleGeometry searched = g;
  compute_lambda(searched);
  ASSERT_EQ(g.lambda.size(), g.size());
  for (size_t i = 0; i < g.size(); ++i) EXPECT_NEAR(g.lambda[i], searched.lambda[i], 1e-8) << i;
  EXPECT_EQ(g.min_distance, 0.01);
  EXPECT_NEAR(searched.min_distance, 0.01, 1e-8);
  // One cube has no neighbour.
  EXPECT_EQ(box_grid_particles({0, 0, 0}, {0.01, 0.01, 0.01}, 0.01).min_distance, 0);
}

// A box-like mesh a whole number of spacings wide, wherever it was modelled: its layers are the
// box grid's, whatever the round-off of its coordinates (a 0.1 m cube at a spacing of 0.01 m gave
// 729 particles at some offsets, 1000 at others: the grid's points lay on its faces).
TEST(GridParticles, ABoxMeshGetsTheBoxLayersWhereverItWasModelled) {
  for (double t : {0.0, 0.3, 1.0, 3.7, 12.34, 100.0, -0.005}) {
    TriMesh cube = box_mesh({0.1, 0.1, 0.1});
    for (Vec3d& v : cube.vertices) v = v + Vec3d{t, t, t};
    const ParticleGeometry g = grid_particles(cube, 0.01, kBudget, "cube");
    EXPECT_EQ(g.size(), 1000u) << t;
    EXPECT_NEAR(g.total_volume(), 1e-3, 1e-12) << t;
  }
  // A hair over a whole number of spacings, or 0.4 of one: the box grid's count (a layer more before).
  for (double side : {0.1 * (1 + 1e-7), 0.104})
    EXPECT_EQ(grid_particles(box_mesh({side, side, side}), 0.01, kBudget, "cube").size(), 1000u) << side;
  EXPECT_EQ(grid_particles(box_mesh({0.3, 0.0101, 0.3}), 0.01, kBudget, "plate").size(), 900u);
  const ParticleGeometry plate = grid_particles(box_mesh({0.3, 0.016, 0.3}), 0.01, kBudget, "plate");
  EXPECT_EQ(plate.size(), 30u * 2 * 30);  // 1.6 spacings thick: two layers, as the box grid has
  const ParticleGeometry sheet = grid_particles(box_mesh({0.3, 0.006, 0.3}), 0.01, kBudget, "sheet");
  EXPECT_EQ(sheet.size(), 30u * 1 * 30);  // less than a spacing: one layer (no particle before)
  // A sphere 0.8 spacings across would be one cube of 3.7 times its volume: none.
  EXPECT_EQ(grid_particles(sphere_mesh(0.004, 0.001), 0.01, kBudget, "speck").size(), 0u);
}

TEST(GridParticles, SpotVolume) {
  PD_REQUIRE_SHARED_MESH(path, "spot.obj");
  const TriMesh spot = spot_solid(path);
  const ParticleGeometry g = grid_particles(spot, 0.02, kBudget, path);
  EXPECT_NEAR(g.total_volume(), signed_volume(spot), 0.02 * signed_volume(spot));
  expect_inside(spot, g);
  expect_symmetric(g.adjacency);
}

TEST(GridParticles, BudgetIsEnforced) {
  try {
    grid_particles(sphere_mesh(1, 0.1), 0.001, 1000000, "big.obj");
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("big.obj: the solid"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at most 1000000 particles"), std::string::npos) << e.what();
  }
}

// ---- tets -------------------------------------------------------------------------------------

TEST(TetParticles, SphereVolumeIsExact) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  const TriMesh sphere = sphere_mesh(1, 0.1);
  TetgenOptions options;
  options.max_volume = 0.001;
  const ParticleGeometry g = tet_particles(sphere, options, kBudget, "sphere");
  // TetGen fills the polyhedron exactly; its files print coordinates rounded, hence 1e-5.
  EXPECT_NEAR(g.total_volume(), signed_volume(sphere), 1e-5 * signed_volume(sphere));
  EXPECT_GT(g.size(), 4188u);
  for (size_t t = 0; t < g.size(); ++t) ASSERT_LE(g.volume[t], 0.001 * (1 + 1e-9));
  expect_inside(sphere, g);
  expect_symmetric(g.adjacency);
  // Every tet has 4 face neighbours but those on the surface, which closes: each of its edges
  // bounds two of its triangles.
  const TriMesh boundary = tet_boundary(g.tets);
  EXPECT_GT(boundary.triangles.size(), 0u);
  std::map<std::pair<int32_t, int32_t>, int> edge_uses;
  for (const Triangle& t : boundary.triangles)
    for (int c = 0; c < 3; ++c) ++edge_uses[{std::min(t[c], t[(c + 1) % 3]), std::max(t[c], t[(c + 1) % 3])}];
  for (const auto& [edge, uses] : edge_uses) ASSERT_EQ(uses, 2) << edge.first << "-" << edge.second;
}

// A flat tet (four coplanar corners) shares the volume of its face neighbour: both particles get
// half, so neither is massless and the total stays.
TEST(TetParticles, FlatTetSharesItsNeighboursVolume) {
  TetMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1},
                   {5, 5, 5}, {6, 5, 5}, {5, 6, 5}, {5, 5, 6}};
  mesh.tets = {{0, 1, 2, 4}, {0, 2, 1, 3}, {5, 6, 7, 8}};  // a tet, the flat one below it, a lone one
  mesh.neighbors = {{-1, -1, -1, 1}, {-1, -1, -1, 0}, {-1, -1, -1, -1}};
  ASSERT_EQ(mesh.volume(1), 0.0);
  const ParticleGeometry g = tet_particles(mesh);
  ASSERT_EQ(g.size(), 3u);
  std::vector<double> volumes = g.volume;
  std::sort(volumes.begin(), volumes.end());
  EXPECT_DOUBLE_EQ(volumes[0], 1.0 / 12);
  EXPECT_DOUBLE_EQ(volumes[1], 1.0 / 12);
  EXPECT_DOUBLE_EQ(volumes[2], 1.0 / 6);
}

// The tension bar's box (`perifrac validate --particles tets`): TetGen leaves flat tets along
// its edges, which get volume; the box's volume is kept.
TEST(TetParticles, BoxHasNoMasslessParticles) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  const TriMesh box = box_mesh({0.055, 0.01, 0.01});
  TetgenOptions options;
  options.max_volume = 2 * 0.0025 * 0.0025 * 0.0025;
  const ParticleGeometry g = tet_particles(box, options, kBudget, "box");
  EXPECT_NEAR(g.total_volume(), 0.055 * 0.01 * 0.01, 1e-5 * 0.055 * 0.01 * 0.01);
  const double mean = g.total_volume() / double(g.size());
  for (size_t t = 0; t < g.size(); ++t) ASSERT_GT(g.volume[t], 1e-6 * mean) << "particle " << t;
}

// tet_keep_surface (-Y): TetGen adds no points on the surface, so the tet mesh's boundary is the
// input's triangles; without it TetGen splits them.
TEST(TetParticles, KeepSurfaceLeavesTheSurfaceTriangles) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  const TriMesh sphere = sphere_mesh(1, 0.2);
  TetgenOptions options;
  options.max_volume = 0.002;
  options.keep_surface = true;
  const ParticleGeometry kept = tet_particles(sphere, options, kBudget, "sphere");
  EXPECT_EQ(tet_boundary(kept.tets).triangles.size(), sphere.triangles.size());
  EXPECT_NEAR(kept.total_volume(), signed_volume(sphere), 1e-5 * signed_volume(sphere));
  for (size_t t = 0; t < kept.size(); ++t) ASSERT_LE(kept.volume[t], 0.002 * (1 + 1e-9));
  expect_symmetric(kept.adjacency);
  options.keep_surface = false;
  const ParticleGeometry split = tet_particles(sphere, options, kBudget, "sphere");
  EXPECT_GT(tet_boundary(split.tets).triangles.size(), sphere.triangles.size());
}

// Barycentres against TetGen's own files, read here independently: each particle's tet is one
// of the file's (particles come in curve order, not the file's), at its barycentre.
TEST(TetParticles, BarycentresMatchTetgenFiles) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  test::ScratchDir dir("tetgen");
  TetgenOptions options;
  options.max_volume = 0.01;
  options.work_dir = dir.file("work");
  const ParticleGeometry g = tet_particles(torus_mesh(1, 0.3, 0.1), options, kBudget, "torus");
  std::ifstream node(dir.file("work/in.1.node")), ele(dir.file("work/in.1.ele"));
  size_t nv = 0, nt = 0, index = 0;
  int dim = 0, a = 0, b = 0;
  node >> nv >> dim >> a >> b;
  std::vector<Vec3d> v(nv);
  for (size_t k = 0; k < nv; ++k) node >> index >> v[k][0] >> v[k][1] >> v[k][2];
  ele >> nt >> dim >> a;
  ASSERT_EQ(nt, g.size());
  std::map<std::array<int32_t, 4>, int> file_tets;  // corners sorted -> times seen
  for (size_t t = 0; t < nt; ++t) {
    std::array<int32_t, 4> c{};
    ele >> index >> c[0] >> c[1] >> c[2] >> c[3];
    std::sort(c.begin(), c.end());
    ++file_tets[c];
  }
  for (size_t t = 0; t < nt; ++t) {
    std::array<int32_t, 4> c = g.tets.tets[t];
    const Vec3d expected = 0.25 * (v[size_t(c[0])] + v[size_t(c[1])] + v[size_t(c[2])] + v[size_t(c[3])]);
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(g.position[t][k], expected[k], 1e-14);
    std::sort(c.begin(), c.end());
    ASSERT_EQ(--file_tets[c], 0) << "tet " << t << " is not one of the file's, or is there twice";
  }
}

TEST(TetParticles, SpotVolume) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  PD_REQUIRE_SHARED_MESH(path, "spot.obj");
  const TriMesh spot = spot_solid(path);
  TetgenOptions options;
  options.max_volume = 2e-5;
  const ParticleGeometry g = tet_particles(spot, options, kBudget, path);
  EXPECT_NEAR(g.total_volume(), signed_volume(spot), 1e-5 * signed_volume(spot));
  // The volume bound holds for every tet (TetGen's mesh optimization, now off, broke it here).
  for (size_t t = 0; t < g.size(); ++t) ASSERT_LE(g.volume[t], 2e-5 * (1 + 1e-9)) << "tet " << t;
  expect_inside(spot, g);
  expect_symmetric(g.adjacency);
}

TEST(TetParticles, FattenedShellOfTheVase) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  const double thickness = 0.006;
  const TriMesh sheet = vase_sheet(0.1, 0.3, 0.006);
  const FattenedShell shell = fattened_shell(sheet, thickness, 4);
  TriMesh solid = shell.solid;
  check_solid(solid, "shell", {});  // closed and outward
  EXPECT_EQ(shell.layer_points.size(), 2 * sheet.vertices.size());
  TetgenOptions options;
  const ParticleGeometry g = shell_particles(sheet, thickness, 4, options, kBudget, "vase");
  // The wall: about (sheet area) x thickness, exactly the shell solid's volume.
  EXPECT_NEAR(g.total_volume(), signed_volume(solid), 1e-5 * signed_volume(solid));
  EXPECT_NEAR(g.total_volume(), surface_area(sheet) * thickness, 0.1 * surface_area(sheet) * thickness);
  expect_inside(solid, g);
  expect_symmetric(g.adjacency);
}

// A closed surface's shell and a solid with a cavity: TetGen leaves the cavity empty (its hole
// list), so the tets fill the solid only, not the ball or box around the cavity.
TEST(TetParticles, CavitiesStayEmpty) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  const TriMesh sphere = sphere_mesh(0.05, 0.006);
  const FattenedShell shell = fattened_shell(sphere, 0.01, 3);
  const ParticleGeometry g = shell_particles(sphere, 0.01, 3, TetgenOptions{}, kBudget, "sphere");
  EXPECT_NEAR(g.total_volume(), signed_volume(shell.solid), 1e-6 * signed_volume(shell.solid));
  EXPECT_LT(g.total_volume(), 0.6 * signed_volume(sphere));
  expect_inside(shell.solid, g);
  // A box with a box-shaped cavity (the inner box's faces turned inward).
  TriMesh hollow = box_mesh({1, 1, 1});
  const TriMesh cavity = box_mesh({0.5, 0.5, 0.5});
  const int32_t base = int32_t(hollow.vertices.size());
  for (const Vec3d& v : cavity.vertices) hollow.vertices.push_back(v);
  for (const Triangle& t : cavity.triangles)
    hollow.triangles.push_back({t[0] + base, t[2] + base, t[1] + base});
  TetgenOptions options;
  options.max_volume = 0.01;
  const ParticleGeometry h = tet_particles(hollow, options, kBudget, "hollow");
  EXPECT_NEAR(h.total_volume(), 1 - 0.125, 1e-9);
  expect_inside(hollow, h);
  // A cube's shell with two inner layers, where TetGen 1.5.0 crashes carving the hole beside the
  // inserted points: the cavity is meshed and its tets dropped.
  TriMesh cube;
  for (int v = 0; v < 8; ++v)
    cube.vertices.push_back({0.05 * (v == 1 || v == 2 || v == 5 || v == 6) - 0.025,
                             0.05 * (v == 2 || v == 3 || v == 6 || v == 7) - 0.025, 0.05 * (v >= 4) - 0.025});
  cube.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  TetgenOptions cube_options;
  cube_options.max_volume = 2.5e-7;
  const FattenedShell cube_shell = fattened_shell(cube, 0.005, 4);
  const ParticleGeometry c = shell_particles(cube, 0.005, 4, cube_options, kBudget, "cube");
  EXPECT_NEAR(c.total_volume(), signed_volume(cube_shell.solid), 1e-9 * signed_volume(cube_shell.solid));
  expect_inside(cube_shell.solid, c);
}

// A shell deeper than the solid turns its inner surface over: refused before TetGen, with the
// depth the surface allows, which lies below the solid's own radii (a sphere's radius, a torus's
// tube) and not far below them; a shell just within it is made.
TEST(TetParticles, AShellDeeperThanTheSolidIsRefusedWithItsLimit) {
  struct Case {
    TriMesh surface;
    double radius;  // the curvature radius that bounds the depth
  };
  for (const Case& c : {Case{sphere_mesh(0.05, 0.005), 0.05}, Case{torus_mesh(0.05, 0.01, 0.002), 0.01}}) {
    double limit = 0;
    try {
      fattened_shell(c.surface, 1.2 * c.radius, 3);
      ADD_FAILURE() << "a shell deeper than the radius " << c.radius << " was made";
    } catch (const ShellThicknessError& e) {
      limit = e.limit;
      EXPECT_NE(std::string(e.what()).find("folds its inner surface over"), std::string::npos) << e.what();
    }
    EXPECT_LT(limit, c.radius);
    EXPECT_GT(limit, 0.8 * c.radius);
    EXPECT_THROW(fattened_shell(c.surface, limit, 3), ShellThicknessError);
    const FattenedShell shell = fattened_shell(c.surface, 0.99 * limit, 3);
    EXPECT_GT(signed_volume(shell.solid), 0);
  }
}

TEST(TetParticles, MissingTetgenIsAClearError) {
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", "/nonexistent", 1);
  try {
    tetrahedralize(box_mesh({1, 1, 1}), {}, "box");
    ADD_FAILURE() << "no MeshError";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("apt-get install tetgen"), std::string::npos) << e.what();
  }
  setenv("PATH", saved.c_str(), 1);
}

TEST(TetParticles, TetgenFailureIsReported) {
  if (!have_tetgen()) GTEST_SKIP() << "tetgen is not installed";
  // Two boxes overlapping: the surfaces intersect each other.
  TriMesh both = box_mesh({1, 1, 1});
  TriMesh other = box_mesh({1, 1, 1});
  transform(other, 1, {0.5, 0.3, 0.2});
  append(both, other);
  try {
    tetrahedralize(both, {}, "overlap.obj");
    ADD_FAILURE() << "no MeshError";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("overlap.obj: tetgen"), std::string::npos) << e.what();
  }
}

// ---- Voronoi ----------------------------------------------------------------------------------

TEST(VoronoiParticles, SphereTilesTheVolume) {
  const double r = 0.1;
  const TriMesh sphere = sphere_mesh(1, 0.05);
  const ParticleGeometry g = voronoi_particles(sphere, r, 7, kBudget, "sphere");
  ASSERT_GT(g.size(), 1000u);
  // The clipped cells partition the polyhedron: their volumes add up to its volume.
  EXPECT_NEAR(g.total_volume(), signed_volume(sphere), 1e-6 * signed_volume(sphere));
  for (double v : g.volume) ASSERT_GT(v, 0);
  expect_inside(sphere, g);
  expect_symmetric(g.adjacency);
  // Poisson-disk: no two sites closer than r; Levine's lambda is at least r.
  EXPECT_GE(g.min_distance, r * (1 - 1e-12));
  // Cells at the surface carry triangles (trimtopes), interior ones none.
  size_t with_triangles = 0;
  for (size_t i = 0; i < g.size(); ++i)
    with_triangles += g.cells.triangle_offset[i + 1] > g.cells.triangle_offset[i];
  EXPECT_GT(with_triangles, 0u);
  EXPECT_LT(with_triangles, g.size());
  EXPECT_EQ(g.cells.face_offset.size(), g.size() + 1);
}

TEST(VoronoiParticles, SpotTilesTheVolume) {
  PD_REQUIRE_SHARED_MESH(path, "spot.obj");
  const TriMesh spot = spot_solid(path);
  const ParticleGeometry g = voronoi_particles(spot, 0.03, 1, kBudget, path);
  EXPECT_NEAR(g.total_volume(), signed_volume(spot), 1e-6 * signed_volume(spot));
  expect_inside(spot, g);
  expect_symmetric(g.adjacency);
  EXPECT_GE(g.min_distance, 0.03 * (1 - 1e-12));
}

TEST(VoronoiParticles, DeterministicForASeed) {
  const TriMesh torus = torus_mesh(1, 0.3, 0.1);
  const ParticleGeometry a = voronoi_particles(torus, 0.1, 5, kBudget, "t");
  const ParticleGeometry b = voronoi_particles(torus, 0.1, 5, kBudget, "t");
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.volume, b.volume);
}

// The cells are made in parallel, each into its own slot: 1, 2 or 3 threads give bit-identical
// sites, volumes, cells, trimtopes and adjacency.
TEST(VoronoiParticles, SameResultForAnyThreadCount) {
  const TriMesh torus = torus_mesh(1, 0.3, 0.05);
  const int saved = omp_get_max_threads();
  std::vector<ParticleGeometry> runs;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    runs.push_back(voronoi_particles(torus, 0.05, 11, kBudget, "torus"));
  }
  omp_set_num_threads(saved);
  ASSERT_GT(runs[0].size(), 5000u);
  for (size_t k = 1; k < runs.size(); ++k) {
    SCOPED_TRACE("threads " + std::to_string(k + 1));
    const ParticleGeometry &a = runs[0], &b = runs[k];
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.volume, b.volume);  // exact equality of doubles
    EXPECT_EQ(a.lambda, b.lambda);
    EXPECT_EQ(a.cells.face_offset, b.cells.face_offset);
    EXPECT_EQ(a.cells.face_site, b.cells.face_site);
    EXPECT_EQ(a.cells.triangle_offset, b.cells.triangle_offset);
    EXPECT_EQ(a.cells.triangles, b.cells.triangles);
    EXPECT_EQ(a.adjacency.offset, b.adjacency.offset);
    EXPECT_EQ(a.adjacency.neighbor, b.adjacency.neighbor);
  }
}

}  // namespace
}  // namespace pd
