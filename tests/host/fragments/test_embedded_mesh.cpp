// Chen's embedded tet mesh (sec. 5.2) on procedural blocks of tets: vertices split only where
// crack faces separate their tets (as many copies as groups), the split surface stays closed with
// the crack faces on the cut, vertices follow the particles (eqs. 19-21), and the crack mesh files
// read back. Then end to end: the frame loop's files and a scene's tet bodies.
#include "host/fragments/embedded_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <utility>

#include "host/fragments/fragment_output.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/tetgen.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kSide = 1e-3;  // cube side [m]
constexpr double kPi = 3.14159265358979323846;

// An nx x ny x nz block of cubes of side kSide from the origin, each cut into the 6 tets around
// its diagonal (Kuhn): the tets of neighbouring cubes meet face to face. Tet t is particle t.
EmbeddedTets box_tets(int nx, int ny, int nz) {
  EmbeddedTets m;
  auto id = [&](int i, int j, int k) { return int32_t(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.vertices.push_back({i * kSide, j * kSide, k * kSide});
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& a : axes) {
          std::array<int, 3> c{i, j, k};
          std::array<int32_t, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[size_t(a[s])];
            t[size_t(s) + 1] = id(c[0], c[1], c[2]);
          }
          m.particle.push_back(int32_t(m.tets.size()));
          m.tets.push_back(t);
        }
  return m;
}

Vec3d barycenter(const EmbeddedTets& m, size_t t) {
  Vec3d b{0, 0, 0};
  for (int32_t v : m.tets[t]) b = b + 0.25 * m.vertices[size_t(v)];
  return b;
}

// One glass particle per tet at its barycentre (horizon 3 cube sides).
SimulationInput tet_input(const EmbeddedTets& m) {
  SimulationInput in;
  in.materials.count = 1;
  in.materials.m[0] = testing::glass_material(kSide);
  const double volume = kSide * kSide * kSide / 6;
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const Vec3d b = barycenter(m, t);
    in.particles.add({real(b[0]), real(b[1]), real(b[2])}, {0, 0, 0}, real(volume), real(2440 * volume),
                     real(1e-3), 0, 0);
  }
  in.step.dt = real(0x1p-23);
  return in;
}

BondLists engine_bonds(const SimulationInput& in) {
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  return bonds;
}

// Breaks, in the family of the particle on the `below` side only, every bond that crosses the
// plane x[axis] = at (the other family keeps its copy: broken in either family is a crack).
void cut(BondLists& bonds, const std::vector<Vec3>& rest, int axis, double at) {
  const BondsView v = bonds.view();
  auto below = [&](int32_t i) { return double((&rest[size_t(i)].x)[axis]) < at; };
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      const int32_t j = bond_partner(v.neighbor[v.slot(i, k)]);
      if (below(i) && !below(j)) bonds.neighbor[size_t(v.slot(i, k))] = ~j;
    }
}

// Closed surfaces of a triangle soup: the vertex-connected pieces, each checked to be closed and
// consistently oriented (every directed edge once, its reverse once), with its enclosed volume.
std::vector<double> closed_piece_volumes(const CrackSurface& s) {
  std::map<std::pair<int32_t, int32_t>, int> edges;
  for (const auto& t : s.triangles)
    for (int i = 0; i < 3; ++i) ++edges[{t[size_t(i)], t[size_t(i + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1) << "edge " << e.first << "-" << e.second;
    EXPECT_EQ(edges.count({e.second, e.first}), 1u) << "open edge " << e.first << "-" << e.second;
  }
  std::vector<int32_t> parent(s.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int32_t i) {
    while (parent[size_t(i)] != i) i = parent[size_t(i)];
    return i;
  };
  for (const auto& t : s.triangles)
    for (int i = 1; i < 3; ++i) parent[size_t(root(t[size_t(i)]))] = root(t[0]);
  std::map<int32_t, double> volume;
  for (const auto& t : s.triangles)
    volume[root(t[0])] +=
        dot(s.vertices[size_t(t[0])], cross(s.vertices[size_t(t[1])], s.vertices[size_t(t[2])])) / 6;
  std::vector<double> out;
  for (const auto& [r, v] : volume) out.push_back(v);
  return out;
}

std::vector<Vec3> shifted(const std::vector<Vec3>& x, Vec3 d) {
  std::vector<Vec3> y = x;
  for (Vec3& p : y) p = {p.x + d.x, p.y + d.y, p.z + d.z};
  return y;
}

TEST(EmbeddedMesh, NothingSplitsWhenNoBondBreaks) {
  const EmbeddedTets box = box_tets(4, 3, 2);
  const SimulationInput in = tet_input(box);
  const BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  mesh.update(bonds, in.particles.rest);
  mesh.update(bonds, shifted(in.particles.rest, {real(2e-4), 0, 0}));
  EXPECT_EQ(mesh.tet_count(), 144u);
  EXPECT_EQ(mesh.vertex_count(), mesh.original_vertex_count());
  EXPECT_EQ(mesh.crack_face_count(), 0u);
  const CrackSurface s = mesh.surface();
  EXPECT_EQ(s.crack_count(), 0u);
  EXPECT_EQ(s.triangles.size(), 2u * 2 * (4 * 3 + 3 * 2 + 4 * 2));  // two triangles per boundary square
  EXPECT_EQ(s.vertices.size(), 5u * 4 * 3 - 3 * 2 * 1);             // the grid points not inside
  const std::vector<double> volumes = closed_piece_volumes(s);
  ASSERT_EQ(volumes.size(), 1u);
  EXPECT_NEAR(volumes[0], 24 * kSide * kSide * kSide, 1e-6 * 24 * kSide * kSide * kSide);  // float positions
}

TEST(EmbeddedMesh, CutBlockSplitsIntoTwoClosedSurfacesWithCrackFacesOnTheCut) {
  const int nx = 4, ny = 3, nz = 2;
  const EmbeddedTets box = box_tets(nx, ny, nz);
  const SimulationInput in = tet_input(box);
  BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  mesh.update(bonds, in.particles.rest);
  cut(bonds, in.particles.rest, 0, 2 * kSide);
  mesh.update(bonds, in.particles.rest);

  // Every vertex on the cut plane got a second copy; every face on it cracked and opened.
  EXPECT_EQ(mesh.vertex_count(), mesh.original_vertex_count() + (ny + 1) * (nz + 1));
  EXPECT_EQ(mesh.crack_face_count(), size_t(2 * ny * nz));
  EXPECT_EQ(mesh.open_crack_face_count(), mesh.crack_face_count());
  const CrackSurface s = mesh.surface();
  EXPECT_EQ(s.crack_count(), size_t(2 * 2 * ny * nz));  // both sides of each face
  for (size_t f = 0; f < s.triangles.size(); ++f)
    if (s.crack[f])
      for (int32_t v : s.triangles[f]) EXPECT_NEAR(s.vertices[size_t(v)][0], 2 * kSide, 1e-15);
  const std::vector<double> volumes = closed_piece_volumes(s);
  ASSERT_EQ(volumes.size(), 2u);
  EXPECT_NEAR(volumes[0], 12 * kSide * kSide * kSide, 1e-18);
  EXPECT_NEAR(volumes[1], 12 * kSide * kSide * kSide, 1e-18);

  // The right half moves away: its crack face moves with it, the left one stays on the cut.
  std::vector<Vec3> moved = in.particles.rest;
  for (Vec3& p : moved)
    if (p.x > 2 * kSide) p.x += real(0.5 * kSide);
  mesh.update(bonds, moved);
  const CrackSurface apart = mesh.surface();
  size_t left = 0, right = 0;
  for (size_t f = 0; f < apart.triangles.size(); ++f) {
    if (!apart.crack[f]) continue;
    const double x = apart.vertices[size_t(apart.triangles[f][0])][0];
    left += std::abs(x - 2 * kSide) < 1e-9;
    right += std::abs(x - 2.5 * kSide) < 1e-9;
  }
  EXPECT_EQ(left, size_t(2 * ny * nz));
  EXPECT_EQ(right, size_t(2 * ny * nz));
  EXPECT_EQ(closed_piece_volumes(apart).size(), 2u);
}

TEST(EmbeddedMesh, VertexOnTwoCutsSplitsIntoFourCopies) {
  const int nx = 4, ny = 4, nz = 2;
  const EmbeddedTets box = box_tets(nx, ny, nz);
  const SimulationInput in = tet_input(box);
  BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  cut(bonds, in.particles.rest, 0, 2 * kSide);
  cut(bonds, in.particles.rest, 1, 1 * kSide);
  mesh.update(bonds, in.particles.rest);
  // Plane vertices off the line x = 2, y = 1 get one extra copy, those on it three.
  const int line = nz + 1;
  EXPECT_EQ(mesh.vertex_count(), mesh.original_vertex_count() + ((ny + 1) * (nz + 1) - line) +
                                     ((nx + 1) * (nz + 1) - line) + 3 * line);
  const std::vector<double> volumes = closed_piece_volumes(mesh.surface());
  ASSERT_EQ(volumes.size(), 4u);
  EXPECT_NEAR(std::accumulate(volumes.begin(), volumes.end(), 0.0), 32 * kSide * kSide * kSide, 1e-18);
}

// A crack face whose tets still meet around all its edges separates nothing: it stays in the
// crack-face set, undrawn, until a split at one of its vertices opens it.
TEST(EmbeddedMesh, CrackFaceIsDrawnOnlyOnceItsVerticesSplit) {
  const EmbeddedTets box = box_tets(4, 4, 4);
  const SimulationInput in = tet_input(box);
  BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  // One face in the plane x = 2 inside the block: between the tets of cubes (1, 1, 1) and (2, 1, 1).
  int32_t a = -1, b = -1;
  for (int32_t i = 0; i < int32_t(in.particles.size()) && b < 0; ++i)
    for (int32_t j = 0; j < int32_t(in.particles.size()) && b < 0; ++j) {
      int shared = 0;
      for (int32_t u : box.tets[size_t(i)])
        for (int32_t w : box.tets[size_t(j)]) shared += u == w;
      const Vec3 p = in.particles.rest[size_t(i)], q = in.particles.rest[size_t(j)];
      if (shared == 3 && p.x < 2 * kSide && q.x > 2 * kSide && p.y > kSide && p.y < 2 * kSide &&
          p.z > kSide && p.z < 2 * kSide)
        a = i, b = j;
    }
  ASSERT_GE(b, 0);
  ASSERT_TRUE(testing::break_bond(bonds, a, b));
  mesh.update(bonds, in.particles.rest);
  EXPECT_EQ(mesh.crack_face_count(), 1u);
  EXPECT_EQ(mesh.open_crack_face_count(), 0u);
  EXPECT_EQ(mesh.vertex_count(), mesh.original_vertex_count());
  EXPECT_EQ(mesh.surface().crack_count(), 0u);
  // The whole plane cracks: now every face on it opens, that one included.
  cut(bonds, in.particles.rest, 0, 2 * kSide);
  mesh.update(bonds, in.particles.rest);
  EXPECT_EQ(mesh.crack_face_count(), 2u * 4 * 4);
  EXPECT_EQ(mesh.open_crack_face_count(), 2u * 4 * 4);
  EXPECT_EQ(closed_piece_volumes(mesh.surface()).size(), 2u);
}

TEST(EmbeddedMesh, RigidTranslationStaysRigid) {
  const EmbeddedTets box = box_tets(4, 3, 2);
  const SimulationInput in = tet_input(box);
  BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  // Constant velocity (0.3, -0.1, 0.2) m/s at 1 ms per frame; the block breaks at frame 3 and the
  // halves keep moving together.
  const Vec3d velocity{0.3, -0.1, 0.2};
  for (int frame = 0; frame <= 6; ++frame) {
    if (frame == 3) cut(bonds, in.particles.rest, 0, 2 * kSide);
    const double t = 1e-3 * frame;
    mesh.update(bonds, shifted(in.particles.rest,
                               {real(velocity[0] * t), real(velocity[1] * t), real(velocity[2] * t)}));
  }
  const CrackSurface s = mesh.surface();
  ASSERT_EQ(s.crack_count(), 24u);
  // Every vertex is its rest position moved by the block's displacement (up to float rounding of
  // the particle positions), so all distances are kept.
  const Vec3d d = 6e-3 * velocity;
  for (const Vec3d& x : s.vertices) {
    const Vec3d r = x - d;
    const Vec3d grid{std::round(r[0] / kSide) * kSide, std::round(r[1] / kSide) * kSide,
                     std::round(r[2] / kSide) * kSide};
    EXPECT_LT(norm(r - grid), 1e-8);
  }
  const std::vector<double> volumes = closed_piece_volumes(s);
  ASSERT_EQ(volumes.size(), 2u);
  EXPECT_NEAR(volumes[0] + volumes[1], 24 * kSide * kSide * kSide, 1e-15);
}

// Under a rigid rotation each vertex moves with the centroid of its particles (eqs. 19-21): off its
// own rotated position by at most that centroid's distance (under 3/4 of a tet edge, sqrt(3) cube
// sides), and back at rest after a full turn.
TEST(EmbeddedMesh, RotationStaysWithinATetAndReturnsAfterAFullTurn) {
  const EmbeddedTets box = box_tets(3, 3, 3);
  const SimulationInput in = tet_input(box);
  const BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  mesh.update(bonds, in.particles.rest);
  const std::vector<Vec3d> rest = mesh.surface().vertices;  // same numbering while nothing splits
  const int frames = 24;
  for (int frame = 1; frame <= frames; ++frame) {
    const double angle = 2 * kPi * frame / frames, c = std::cos(angle), s = std::sin(angle);
    std::vector<Vec3> x = in.particles.rest;
    for (Vec3& p : x) p = {real(c * p.x - s * p.y), real(s * p.x + c * p.y), p.z};
    mesh.update(bonds, x);
    const std::vector<Vec3d> now = mesh.surface().vertices;
    ASSERT_EQ(now.size(), rest.size());
    for (size_t v = 0; v < now.size(); ++v) {
      const Vec3d turned{c * rest[v][0] - s * rest[v][1], s * rest[v][0] + c * rest[v][1], rest[v][2]};
      EXPECT_LT(norm(now[v] - turned),
                2 * std::abs(std::sin(angle / 2)) * 0.75 * std::sqrt(3.0) * kSide + 1e-9);
      if (frame == frames) EXPECT_LT(norm(now[v] - rest[v]), 1e-9);
    }
  }
}

TEST(EmbeddedMesh, RejectsFaceNeighboursWithoutABond) {
  const EmbeddedTets box = box_tets(2, 1, 1);
  SimulationInput in = tet_input(box);
  in.materials.m[0] = testing::glass_material(kSide, 0.1);  // horizon shorter than the tets
  const BondLists bonds = engine_bonds(in);
  EXPECT_THROW(EmbeddedTetMesh(box, bonds, in.particles.rest, in.particles.mass), std::invalid_argument);
}

using EmbeddedMeshFiles = testing::TempDirTest;

TEST_F(EmbeddedMeshFiles, ObjAndPlyRoundTrip) {
  const EmbeddedTets box = box_tets(4, 3, 2);
  const SimulationInput in = tet_input(box);
  BondLists bonds = engine_bonds(in);
  EmbeddedTetMesh mesh(box, bonds, in.particles.rest, in.particles.mass);
  cut(bonds, in.particles.rest, 0, 2 * kSide);
  mesh.update(bonds, shifted(in.particles.rest, {real(0.1), real(-0.2), real(0.3)}));
  const CrackSurface s = mesh.surface();
  ASSERT_GT(s.crack_count(), 0u);
  write_crack_obj(path("m.obj"), s, "frame 1");
  write_crack_ply(path("m.ply"), s, "frame 1");
  for (const char* name : {"m.obj", "m.ply"}) {
    SCOPED_TRACE(name);
    const CrackSurface back = read_crack_mesh(path(name));
    EXPECT_EQ(back.triangles, s.triangles);  // surface triangles come first in both
    EXPECT_EQ(back.crack, s.crack);
    ASSERT_EQ(back.vertices.size(), s.vertices.size());
    for (size_t v = 0; v < s.vertices.size(); ++v) EXPECT_LT(norm(back.vertices[v] - s.vertices[v]), 1e-7);
    // Generic mesh readers (as other tools read them) see the same triangles.
    EXPECT_EQ(read_mesh(path(name)).triangles.size(), s.triangles.size());
  }
  EXPECT_EQ(crack_mesh_file_name(42, "ply"), "crack_mesh_00042.ply");
  EXPECT_THROW(read_crack_mesh(path("m.obj") + ".ply"), MeshError);
}

// The frame loop writes crack_mesh_NNNNN.obj / .ply for tet bodies.
TEST_F(EmbeddedMeshFiles, FragmentOutputWritesCrackMeshesEveryFrame) {
  const EmbeddedTets box = box_tets(4, 3, 2);
  const SimulationInput in = tet_input(box);
  BondLists bonds = engine_bonds(in);
  std::vector<std::pair<int32_t, int32_t>> pairs;
  for (size_t t = 0; t < box.tets.size(); ++t)
    for (size_t u = t + 1; u < box.tets.size(); ++u) {
      int shared = 0;
      for (int32_t a : box.tets[t])
        for (int32_t b : box.tets[u]) shared += a == b;
      if (shared == 3) pairs.emplace_back(int32_t(t), int32_t(u));
    }
  FragmentOutput out(in, bonds, {dir_.string(), 0, false, false},
                     adjacency_from_pairs(box.tets.size(), pairs), box);
  ASSERT_NE(out.embedded_mesh(), nullptr);
  FrameData f0;
  f0.position = in.particles.rest;
  f0.velocity.assign(in.particles.size(), {0, 0, 0});
  f0.damage.assign(in.particles.size(), 0);
  f0.body.assign(in.particles.size(), 0);
  out.process(f0, bonds);
  cut(bonds, in.particles.rest, 0, 2 * kSide);
  FrameData f1 = f0;
  f1.frame = 1;
  EXPECT_EQ(out.process(f1, bonds).count, 2u);
  EXPECT_EQ(read_crack_mesh(path("crack_mesh_00000.obj")).crack_count(), 0u);
  EXPECT_EQ(read_crack_mesh(path("crack_mesh_00000.ply")).crack_count(), 0u);
  EXPECT_EQ(read_crack_mesh(path("crack_mesh_00001.obj")).crack_count(), 24u);
  EXPECT_EQ(read_crack_mesh(path("crack_mesh_00001.ply")).crack, out.crack_surface().crack);
}

// Scene set-up carries the tet meshes of tet bodies, tet t standing for the particle at its
// barycentre, after the particles of earlier bodies.
TEST(SceneBodies, TetBodiesCarryTheirMesh) {
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  const Scene scene = parse_scene(R"(
[materials.glass]
density = 2000
bulk_modulus = 4.3e10
strain_limit = 0.001
[[bodies]]
material = "glass"
size = [0.04, 0.02, 0.02]
spacing = 0.01
center = [0, -1, 0]
[[bodies]]
material = "glass"
shape = "sphere"
radius = 0.05
spacing = 0.01
particles = "tets"
)",
                                  "tets.toml");
  const SetupResult setup = setup_scene(scene, {});
  const ParticleSet& ps = setup.input.particles;
  const size_t grid = 16;  // 4 x 2 x 2 cubes of the first body
  ASSERT_EQ(setup.embedded.tets.size(), ps.size() - grid);
  for (size_t t = 0; t < setup.embedded.tets.size(); ++t) {
    const size_t p = size_t(setup.embedded.particle[t]);
    ASSERT_EQ(p, grid + t);
    const Vec3d b = barycenter(setup.embedded, t);
    ASSERT_LT(std::hypot(b[0] - ps.rest[p].x, b[1] - ps.rest[p].y, b[2] - ps.rest[p].z), 1e-6);
  }
  const BondLists bonds = engine_bonds(setup.input);
  EmbeddedTetMesh mesh(setup.embedded, bonds, ps.rest, ps.mass);
  mesh.update(bonds, ps.rest);
  double volume = 0;
  for (size_t p = grid; p < ps.size(); ++p) volume += ps.volume[p];
  const std::vector<double> volumes = closed_piece_volumes(mesh.surface());
  ASSERT_EQ(volumes.size(), 1u);
  EXPECT_NEAR(volumes[0], volume, 1e-6 * volume);
}

}  // namespace
}  // namespace pd
