// Chen's embedded mesh (sec. 5.2) on procedural blocks of tets and of cubes: vertices split only
// where crack faces separate their elements (as many copies as groups), the split surface stays
// closed with the crack faces on the cut, vertices follow the particles (eqs. 19-21 in the
// fragment's frame: rigid motions exactly, deformation within the stated bound). Then end to end:
// the frame loop's files and a scene's tet bodies.
#include "host/fragments/embedded_mesh.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <numeric>
#include <optional>
#include <utility>

#include "host/fragments/cube_complex.h"
#include "host/fragments/fragment_output.h"
#include "host/fragments/particle_elements.h"
#include "host/fragments/voronoi_complex.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tetgen.h"
#include "host/geometry/voronoi_particles.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "tests/host/fragments/fragment_fixtures.h"
#include "tests/host/fragments/mesh_checks.h"
#include "tests/support/fixtures.h"

namespace pd {
namespace {

constexpr double kSide = 1e-3;  // cube side [m]
constexpr double kPi = 3.14159265358979323846;

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

// The pairs of elements that share a face.
ElementAdjacency face_adjacency(const ElementComplex& c) {
  std::vector<std::pair<int32_t, int32_t>> pairs;
  for (size_t e = 0; e < c.size(); ++e)
    for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f)
      if (c.face_other[size_t(f)] >= 0) pairs.emplace_back(int32_t(e), c.face_other[size_t(f)]);
  return adjacency_from_pairs(c.size(), std::move(pairs));
}

// A block of elements with its particles, families and embedded mesh. update() finds the
// fragments and their fits for the given positions, as FragmentOutput does, then moves the mesh.
struct Block {
  SimulationInput in;
  BondLists bonds;
  ElementAdjacency adjacency;
  std::optional<EmbeddedMesh> mesh;

  void update(const std::vector<Vec3>& x) {
    ComponentFinder finder(adjacency, bonds);
    Components c;
    finder.find(bonds, c);
    std::vector<Fragment> fits;
    align_fragments(c, in.particles.rest, x, in.particles.mass, fits);
    mesh->update(bonds, x, c, fits);
  }
  void update() { update(in.particles.rest); }
};

// An nx x ny x nz block of cubes of side kSide from the origin, each cut into 6 tets.
Block tet_block(int nx, int ny, int nz) {
  Block b;
  const EmbeddedTets box = testing::box_tets(nx, ny, nz, kSide);
  b.in = tet_input(box);
  make_cpu_engine(b.in)->read_bonds(b.bonds);
  ElementComplex c = assemble(box.tets.size(), {tet_complex(box)});
  b.adjacency = face_adjacency(c);
  b.mesh.emplace(std::move(c), b.adjacency, b.bonds, b.in.particles.rest, b.in.particles.mass);
  return b;
}

// The same block as nx x ny x nz grid cubes (particles at the cube centres).
Block cube_block(int nx, int ny, int nz) {
  Block b;
  b.in = testing::lattice_block(nx, ny, nz, kSide);
  for (Vec3& p : b.in.particles.rest)
    p = {real(p.x + 0.5 * kSide), real(p.y + 0.5 * kSide), real(p.z + 0.5 * kSide)};
  make_cpu_engine(b.in)->read_bonds(b.bonds);
  const std::vector<real> spacing = particle_spacing(b.in.particles, b.in.materials);
  b.adjacency = grid_adjacency(b.bonds, b.in.particles.rest, spacing);
  std::vector<int32_t> all(b.in.particles.size());
  std::iota(all.begin(), all.end(), 0);
  b.mesh.emplace(cube_complex(b.adjacency, b.in.particles.rest, spacing, all), b.adjacency, b.bonds,
                 b.in.particles.rest, b.in.particles.mass);
  return b;
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

std::vector<Vec3> shifted(const std::vector<Vec3>& x, Vec3 d) {
  std::vector<Vec3> y = x;
  for (Vec3& p : y) p = {p.x + d.x, p.y + d.y, p.z + d.z};
  return y;
}

// Distance of x to the nearest point of the lattice kSide Z^3.
double off_grid(const Vec3d& x) {
  const Vec3d g{std::round(x[0] / kSide) * kSide, std::round(x[1] / kSide) * kSide,
                std::round(x[2] / kSide) * kSide};
  return norm(x - g);
}

TEST(EmbeddedMesh, NothingSplitsWhenNoBondBreaks) {
  for (const bool cubes : {false, true}) {
    SCOPED_TRACE(cubes ? "cubes" : "tets");
    Block b = cubes ? cube_block(4, 3, 2) : tet_block(4, 3, 2);
    b.update();
    b.update(shifted(b.in.particles.rest, {real(2e-4), 0, 0}));
    EXPECT_EQ(b.mesh->element_count(), cubes ? 24u : 144u);
    EXPECT_EQ(b.mesh->vertex_count(), b.mesh->original_vertex_count());
    EXPECT_EQ(b.mesh->crack_face_count(), 0u);
    const CrackSurface s = b.mesh->surface();
    EXPECT_EQ(s.crack_count(), 0u);
    EXPECT_EQ(s.triangles.size(), 2u * 2 * (4 * 3 + 3 * 2 + 4 * 2));  // two triangles per boundary square
    EXPECT_EQ(s.vertices.size(), 5u * 4 * 3 - 3 * 2 * 1);             // the grid points not inside
    const std::vector<double> volumes = testing::closed_piece_volumes(s);
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_NEAR(volumes[0], 24 * kSide * kSide * kSide,
                1e-6 * 24 * kSide * kSide * kSide);  // float positions
  }
}

TEST(EmbeddedMesh, CutBlockSplitsIntoTwoClosedSurfacesWithCrackFacesOnTheCut) {
  const int nx = 4, ny = 3, nz = 2;
  for (const bool cubes : {false, true}) {
    SCOPED_TRACE(cubes ? "cubes" : "tets");
    Block b = cubes ? cube_block(nx, ny, nz) : tet_block(nx, ny, nz);
    b.update();
    cut(b.bonds, b.in.particles.rest, 0, 2 * kSide);
    b.update();

    // Every vertex on the cut plane got a second copy; every face on it cracked and opened.
    const size_t faces = size_t((cubes ? 1 : 2) * ny * nz);  // element faces on the plane
    EXPECT_EQ(b.mesh->vertex_count(), b.mesh->original_vertex_count() + (ny + 1) * (nz + 1));
    EXPECT_EQ(b.mesh->crack_face_count(), faces);
    EXPECT_EQ(b.mesh->open_crack_face_count(), faces);
    const CrackSurface s = b.mesh->surface();
    EXPECT_EQ(s.crack_count(), size_t(2 * 2 * ny * nz));  // both sides of each square, two triangles each
    // Tet vertices are given in double; cube corners come from the float particle positions.
    const double on_plane = cubes ? 1e-9 : 1e-12;
    for (size_t f = 0; f < s.triangles.size(); ++f)
      if (s.crack[f]) {
        for (int32_t v : s.triangles[f]) EXPECT_NEAR(s.vertices[size_t(v)][0], 2 * kSide, on_plane);
      }
    // Each triangle is owned by the particle whose element it bounds: its centre lies within the
    // element, and a crack triangle faces away from its owner's side of the cut.
    ASSERT_EQ(s.particle.size(), s.triangles.size());
    for (size_t f = 0; f < s.triangles.size(); ++f) {
      const auto& t = s.triangles[f];
      const Vec3d& a = s.vertices[size_t(t[0])];
      const Vec3d centre = (1.0 / 3) * (a + s.vertices[size_t(t[1])] + s.vertices[size_t(t[2])]);
      const Vec3& owner = b.in.particles.rest[size_t(s.particle[f])];
      EXPECT_LT(norm(centre - Vec3d{owner.x, owner.y, owner.z}), 0.87 * kSide) << "triangle " << f;
      if (!s.crack[f]) continue;
      const double out_x = cross(s.vertices[size_t(t[1])] - a, s.vertices[size_t(t[2])] - a)[0];
      EXPECT_EQ(out_x > 0, owner.x < 2 * kSide) << "triangle " << f;
    }
    const std::vector<double> volumes = testing::closed_piece_volumes(s);
    ASSERT_EQ(volumes.size(), 2u);
    EXPECT_NEAR(volumes[0], 12 * kSide * kSide * kSide, 1e-6 * 12 * kSide * kSide * kSide);
    EXPECT_NEAR(volumes[1], 12 * kSide * kSide * kSide, 1e-6 * 12 * kSide * kSide * kSide);

    // The right half moves away: its crack face moves with it, the left one stays on the cut.
    std::vector<Vec3> moved = b.in.particles.rest;
    for (Vec3& p : moved)
      if (p.x > 2 * kSide) p.x += real(0.5 * kSide);
    b.update(moved);
    const CrackSurface apart = b.mesh->surface();
    size_t left = 0, right = 0;
    for (size_t f = 0; f < apart.triangles.size(); ++f) {
      if (!apart.crack[f]) continue;
      const double x = apart.vertices[size_t(apart.triangles[f][0])][0];
      left += std::abs(x - 2 * kSide) < 1e-9;
      right += std::abs(x - 2.5 * kSide) < 1e-9;
    }
    EXPECT_EQ(left, size_t(2 * ny * nz));
    EXPECT_EQ(right, size_t(2 * ny * nz));
    EXPECT_EQ(testing::closed_piece_volumes(apart).size(), 2u);
  }
}

TEST(EmbeddedMesh, VertexOnTwoCutsSplitsIntoFourCopies) {
  const int nx = 4, ny = 4, nz = 2;
  for (const bool cubes : {false, true}) {
    SCOPED_TRACE(cubes ? "cubes" : "tets");
    Block b = cubes ? cube_block(nx, ny, nz) : tet_block(nx, ny, nz);
    cut(b.bonds, b.in.particles.rest, 0, 2 * kSide);
    cut(b.bonds, b.in.particles.rest, 1, 1 * kSide);
    b.update();
    // Plane vertices off the line x = 2, y = 1 get one extra copy, those on it three.
    const int line = nz + 1;
    EXPECT_EQ(b.mesh->vertex_count(), b.mesh->original_vertex_count() + ((ny + 1) * (nz + 1) - line) +
                                          ((nx + 1) * (nz + 1) - line) + 3 * line);
    const std::vector<double> volumes = testing::closed_piece_volumes(b.mesh->surface());
    ASSERT_EQ(volumes.size(), 4u);
    EXPECT_NEAR(std::accumulate(volumes.begin(), volumes.end(), 0.0), 32 * kSide * kSide * kSide,
                1e-6 * 32 * kSide * kSide * kSide);
  }
}

// The surface of a block cut into 64 pieces, walked in parallel blocks of elements, is the serial
// walk's: the original surface's triangles, then the cracks', each group in element order; vertices
// numbered in order of first use, each used; the same with one thread as with all; closed pieces.
TEST(EmbeddedMesh, ShatteredSurfaceIsTheWalkInElementOrder) {
  const int n = 12;  // 10,368 tets: ten blocks of the walk on each side
  Block b = tet_block(n, n, n);
  for (int axis = 0; axis < 3; ++axis)
    for (int at = 3; at < n; at += 3) cut(b.bonds, b.in.particles.rest, axis, at * kSide);
  b.update();
  const CrackSurface s = b.mesh->surface();
  ASSERT_EQ(s.crack.size(), s.triangles.size());
  ASSERT_EQ(s.particle.size(), s.triangles.size());
  EXPECT_EQ(s.crack_count(), size_t(2 * 2 * 3 * 3 * n * n));  // 9 planes, two sides, 2 tets a square
  int32_t next = 0;                                           // the first vertex not yet used
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    if (t > 0) {
      ASSERT_GE(s.crack[t], s.crack[t - 1]) << "triangle " << t;
      if (s.crack[t] == s.crack[t - 1]) {
        ASSERT_GE(s.particle[t], s.particle[t - 1]) << "triangle " << t;
      }
    }
    for (const int32_t v : s.triangles[t]) {
      ASSERT_LE(v, next) << "triangle " << t;
      next += v == next;
    }
  }
  EXPECT_EQ(size_t(next), s.vertices.size());
  EXPECT_EQ(testing::closed_piece_volumes(s).size(), 64u);

  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const CrackSurface one = b.mesh->surface();
  omp_set_num_threads(threads);
  EXPECT_EQ(one.vertices, s.vertices);
  EXPECT_EQ(one.triangles, s.triangles);
  EXPECT_EQ(one.crack, s.crack);
  EXPECT_EQ(one.particle, s.particle);
}

// A crack face whose tets still meet around all its edges separates nothing: it stays in the
// crack-face set, undrawn, until a split at one of its vertices opens it.
TEST(EmbeddedMesh, CrackFaceIsDrawnOnlyOnceItsVerticesSplit) {
  Block b = tet_block(4, 4, 4);
  const EmbeddedTets box = testing::box_tets(4, 4, 4, kSide);
  // One face in the plane x = 2 inside the block: between the tets of cubes (1, 1, 1) and (2, 1, 1).
  const std::vector<Vec3>& rest = b.in.particles.rest;
  int32_t p = -1, q = -1;
  for (int32_t i = 0; i < int32_t(rest.size()) && q < 0; ++i)
    for (int32_t j = 0; j < int32_t(rest.size()) && q < 0; ++j) {
      int shared = 0;
      for (int32_t u : box.tets[size_t(i)])
        for (int32_t w : box.tets[size_t(j)]) shared += u == w;
      if (shared == 3 && rest[size_t(i)].x < 2 * kSide && rest[size_t(j)].x > 2 * kSide &&
          rest[size_t(i)].y > kSide && rest[size_t(i)].y < 2 * kSide && rest[size_t(i)].z > kSide &&
          rest[size_t(i)].z < 2 * kSide)
        p = i, q = j;
    }
  ASSERT_GE(q, 0);
  ASSERT_TRUE(testing::break_bond(b.bonds, p, q));
  b.update();
  EXPECT_EQ(b.mesh->crack_face_count(), 1u);
  EXPECT_EQ(b.mesh->open_crack_face_count(), 0u);
  EXPECT_EQ(b.mesh->vertex_count(), b.mesh->original_vertex_count());
  EXPECT_EQ(b.mesh->surface().crack_count(), 0u);
  // The whole plane cracks: now every face on it opens, that one included.
  cut(b.bonds, rest, 0, 2 * kSide);
  b.update();
  EXPECT_EQ(b.mesh->crack_face_count(), 2u * 4 * 4);
  EXPECT_EQ(b.mesh->open_crack_face_count(), 2u * 4 * 4);
  EXPECT_EQ(testing::closed_piece_volumes(b.mesh->surface()).size(), 2u);
}

// A block that breaks in two, each half then turning about its own axis and moving: every vertex
// is its rest position carried by its half's rigid motion, up to the float rounding of the
// particle positions (6e-8 relative to coordinates of up to 6 mm: 4e-10 m; 2.5e-10 m seen, checked
// to 1e-9 m, a millionth of a cube side); the halves stay closed with their rest volumes. Checked
// every frame through two full turns.
TEST(EmbeddedMesh, RigidMotionsStayRigid) {
  for (const bool cubes : {false, true}) {
    SCOPED_TRACE(cubes ? "cubes" : "tets");
    Block b = cubes ? cube_block(4, 3, 2) : tet_block(4, 3, 2);
    const Eigen::Vector3d axis_left = Eigen::Vector3d(0.3, -0.5, 1).normalized(),
                          axis_right = Eigen::Vector3d::UnitX();
    auto motion = [&](bool right, double t) {
      const double angle = 2 * kPi * t * (right ? -1 : 1);
      Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
      m.rotate(Eigen::AngleAxisd(angle, right ? axis_right : axis_left));
      m.translation() = Eigen::Vector3d(0.3, -0.1, 0.2) * 1e-3 * t +
                        (right ? Eigen::Vector3d(2e-3, 0, 0) : Eigen::Vector3d::Zero());
      return m;
    };
    const int frames = 16;
    for (int frame = 0; frame <= frames; ++frame) {
      if (frame == 3) cut(b.bonds, b.in.particles.rest, 0, 2 * kSide);
      const double t = 2.0 * frame / frames;  // two turns
      std::vector<Vec3> x = b.in.particles.rest;
      for (Vec3& p : x) {
        const bool right = frame >= 3 && p.x > 2 * kSide;
        const Eigen::Vector3d q = motion(right, frame >= 3 ? t : 0) * Eigen::Vector3d(p.x, p.y, p.z);
        p = {real(q.x()), real(q.y()), real(q.z())};
      }
      b.update(x);
      const CrackSurface s = b.mesh->surface();
      double worst = 0;
      for (const Vec3d& v : s.vertices) {
        double best = HUGE_VAL;
        for (const bool right : {false, true}) {
          const Eigen::Vector3d r =
              motion(right, frame >= 3 ? t : 0).inverse() * Eigen::Vector3d(v[0], v[1], v[2]);
          best = std::min(best, off_grid({r.x(), r.y(), r.z()}));
        }
        worst = std::max(worst, best);
      }
      EXPECT_LT(worst, 1e-9) << "frame " << frame;
      const std::vector<double> volumes = testing::closed_piece_volumes(s);
      ASSERT_EQ(volumes.size(), frame >= 3 ? 2u : 1u);
      EXPECT_NEAR(std::accumulate(volumes.begin(), volumes.end(), 0.0), 24 * kSide * kSide * kSide,
                  1e-6 * 24 * kSide * kSide * kSide);
    }
  }
}

// A resumed run rebuilds the mesh from the bonds at once: it must write what the run split frame by
// frame writes (groups depend only on the crack set, positions only on the particles and fits).
TEST(EmbeddedMesh, RebuiltMeshEqualsTheOneSplitFrameByFrame) {
  for (const bool cubes : {false, true}) {
    SCOPED_TRACE(cubes ? "cubes" : "tets");
    Block a = cubes ? cube_block(4, 4, 3) : tet_block(4, 4, 3);
    const std::vector<Vec3> rest = a.in.particles.rest;
    std::vector<Vec3> x;
    for (int frame = 0; frame < 4; ++frame) {
      if (frame == 1) testing::break_bond(a.bonds, 5, a.bonds.neighbor[size_t(a.bonds.view().slot(5, 0))]);
      if (frame == 2) cut(a.bonds, rest, 0, 2 * kSide);
      if (frame == 3) cut(a.bonds, rest, 1, 1 * kSide);
      x = shifted(rest, {real(1e-4 * frame), 0, real(-2e-4 * frame)});
      for (Vec3& p : x)
        if (p.x > 2 * kSide) p.y += real(3e-4 * frame);
      a.update(x);
    }
    Block b = cubes ? cube_block(4, 4, 3) : tet_block(4, 4, 3);
    b.bonds = a.bonds;
    b.update(x);
    const CrackSurface sa = a.mesh->surface(), sb = b.mesh->surface();
    EXPECT_EQ(sa.triangles, sb.triangles);
    EXPECT_EQ(sa.crack, sb.crack);
    EXPECT_EQ(sa.vertices, sb.vertices);
    EXPECT_EQ(a.mesh->open_crack_face_count(), b.mesh->open_crack_face_count());
  }
}

// Deformation is followed only through the particles' centroid: a vertex is off the deformed
// place of its rest position by (F - R) (x_v - c) for a homogeneous deformation F with fitted
// rotation R, c the centroid of the vertex's particles, at most |F - R| times an element's
// diameter (sqrt(3) cube sides). A block turned and stretched by 2% along its x axis: the error
// stays within that bound and is of its order (a corner vertex is half a diagonal from its cube's
// centre).
TEST(EmbeddedMesh, StretchIsFollowedWithinTheStatedBound) {
  Block b = cube_block(4, 3, 2);
  const double stretch = 0.02;
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d f = r * Eigen::Vector3d(1 + stretch, 1, 1).asDiagonal();
  std::vector<Vec3> x = b.in.particles.rest;
  for (Vec3& p : x) {
    const Eigen::Vector3d q = f * Eigen::Vector3d(p.x, p.y, p.z);
    p = {real(q.x()), real(q.y()), real(q.z())};
  }
  b.update(x);
  // Each surface vertex against the nearest deformed grid point.
  const CrackSurface s = b.mesh->surface();
  const Eigen::Matrix3d back = f.inverse();
  double worst = 0;
  for (const Vec3d& v : s.vertices) {
    const Eigen::Vector3d rest = back * Eigen::Vector3d(v[0], v[1], v[2]);
    const Eigen::Vector3d grid = (rest / kSide).array().round().matrix() * kSide;
    worst = std::max(worst, (f * grid - Eigen::Vector3d(v[0], v[1], v[2])).norm());
  }
  EXPECT_LE(worst, stretch * std::sqrt(3.0) * kSide);
  EXPECT_GE(worst, 0.25 * stretch * kSide);
}

// Voronoi cells cut to a sphere, the bonds across the plane x = 0 broken: the split surface is two
// closed pieces, each enclosing its particles' volume; its crack faces are the cells' faces between
// the halves, as many as the cells' faces on the object's surface are not.
TEST(EmbeddedMesh, VoronoiSphereSplitsAlongItsCellFaces) {
  const ParticleGeometry g = voronoi_particles(sphere_mesh(0.02, 0.003), 0.004, 3, 100000, "sphere");
  Block b;
  b.in.materials.count = 1;
  b.in.materials.m[0] = testing::glass_material(0.004);
  for (size_t i = 0; i < g.size(); ++i)
    b.in.particles.add({real(g.position[i][0]), real(g.position[i][1]), real(g.position[i][2])}, {0, 0, 0},
                       real(g.volume[i]), real(2440 * g.volume[i]), real(1e-3), 0, 0);
  b.in.step.dt = real(0x1p-23);
  make_cpu_engine(b.in)->read_bonds(b.bonds);
  b.adjacency = g.adjacency;
  b.mesh.emplace(voronoi_complex(g), b.adjacency, b.bonds, b.in.particles.rest, b.in.particles.mass);
  b.update();
  EXPECT_EQ(b.mesh->vertex_count(), b.mesh->original_vertex_count());
  ASSERT_EQ(testing::closed_piece_volumes(b.mesh->surface()).size(), 1u);
  cut(b.bonds, b.in.particles.rest, 0, 0.0);
  b.update();
  const CrackSurface s = b.mesh->surface();
  EXPECT_GT(s.crack_count(), 0u);
  double left = 0, right = 0;
  for (size_t i = 0; i < g.size(); ++i) (b.in.particles.rest[i].x < 0 ? left : right) += g.volume[i];
  std::vector<double> volumes = testing::closed_piece_volumes(s);
  ASSERT_EQ(volumes.size(), 2u);
  // Both sides hold their cells' exact volumes (in double, to round-off: 1e-11 as for the pieces).
  const double a = volumes[0], c = volumes[1];
  EXPECT_NEAR(std::min(a, c), std::min(left, right), 1e-11 * left);
  EXPECT_NEAR(std::max(a, c), std::max(left, right), 1e-11 * left);
}

// Touching tets with no bond path between them (families left empty): their faces never held,
// so each tet is a closed piece of its own from the start.
TEST(EmbeddedMesh, FaceNeighboursWithNoBondPathAreCracksFromTheStart) {
  const EmbeddedTets box = testing::box_tets(2, 1, 1, kSide);
  const SimulationInput in = tet_input(box);
  const BondLists bonds = testing::bond_lists(std::vector<std::vector<int32_t>>(box.tets.size()));
  ElementComplex c = assemble(box.tets.size(), {tet_complex(box)});
  const ElementAdjacency adjacency = face_adjacency(c);
  const EmbeddedMesh mesh(c, adjacency, bonds, in.particles.rest, in.particles.mass);
  EXPECT_EQ(testing::closed_piece_volumes(mesh.surface()).size(), box.tets.size());
}

// Voronoi cells at delta = 2 lambda: some touching cells are farther apart than the horizon and
// hold through common neighbours, so the sphere is still one closed piece; cut across x = 0 it
// splits in two, those cells' faces included.
TEST(EmbeddedMesh, VoronoiCellsBeyondTheHorizonHoldThroughCommonNeighbours) {
  const ParticleGeometry g = voronoi_particles(sphere_mesh(0.02, 0.003), 0.004, 3, 100000, "sphere");
  Block b;
  b.in.materials.count = 1;
  b.in.materials.m[0] = testing::glass_material(0.004, 1.5);
  for (size_t i = 0; i < g.size(); ++i)
    b.in.particles.add({real(g.position[i][0]), real(g.position[i][1]), real(g.position[i][2])}, {0, 0, 0},
                       real(g.volume[i]), real(2440 * g.volume[i]), real(1e-3), 0, 0);
  b.in.step.dt = real(0x1p-23);
  make_cpu_engine(b.in)->read_bonds(b.bonds);
  b.adjacency = g.adjacency;
  const FaceLinks links = ComponentFinder(b.adjacency, b.bonds).links();
  EXPECT_GT(links.indirect(), 0u);
  EXPECT_EQ(links.unlinked(), 0u);
  b.mesh.emplace(voronoi_complex(g), b.adjacency, b.bonds, b.in.particles.rest, b.in.particles.mass);
  b.update();
  ASSERT_EQ(testing::closed_piece_volumes(b.mesh->surface()).size(), 1u);
  cut(b.bonds, b.in.particles.rest, 0, 0.0);
  b.update();
  EXPECT_EQ(testing::closed_piece_volumes(b.mesh->surface()).size(), 2u);
}

// Elements that are not in particle order are refused.
TEST(EmbeddedMesh, RejectsElementsOutOfParticleOrder) {
  const EmbeddedTets box = testing::box_tets(2, 1, 1, kSide);
  SimulationInput in = tet_input(box);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  ElementComplex shuffled = tet_complex(box);
  const ElementAdjacency adjacency = face_adjacency(assemble(box.tets.size(), {tet_complex(box)}));
  std::swap(shuffled.particle[0], shuffled.particle[1]);
  EXPECT_THROW(EmbeddedMesh(shuffled, adjacency, bonds, in.particles.rest, in.particles.mass),
               std::invalid_argument);
}

using EmbeddedMeshFiles = testing::TempDirTest;

// The frame loop writes crack_mesh_NNNNN.obj / .ply, here for tet bodies.
TEST_F(EmbeddedMeshFiles, FragmentOutputWritesCrackMeshesEveryFrame) {
  const EmbeddedTets box = testing::box_tets(4, 3, 2, kSide);
  const SimulationInput in = tet_input(box);
  BondLists bonds;
  make_cpu_engine(in)->read_bonds(bonds);
  FragmentOutput out(in, bonds, {dir_.string(), 0, false}, face_adjacency(tet_complex(box)), box);
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
// barycentre, after the particles of earlier bodies; with the grid body's cubes they make one
// element per particle, and the embedded mesh of both bodies is closed at rest.
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
  BondLists bonds;
  make_cpu_engine(setup.input)->read_bonds(bonds);
  const std::vector<real> spacing = particle_spacing(ps, setup.input.materials);
  Block b;
  b.in = setup.input;
  b.bonds = bonds;
  b.adjacency = setup.adjacency;
  b.mesh.emplace(particle_elements(ps.rest, spacing, setup.adjacency, setup.embedded, {}), setup.adjacency,
                 bonds, ps.rest, ps.mass);
  b.update();
  double tets = 0;
  for (size_t p = grid; p < ps.size(); ++p) tets += ps.volume[p];
  std::vector<double> volumes = testing::closed_piece_volumes(b.mesh->surface());
  ASSERT_EQ(volumes.size(), 2u);
  std::sort(volumes.begin(), volumes.end());
  EXPECT_NEAR(volumes[0], 16e-6, 1e-6 * 16e-6);
  EXPECT_NEAR(volumes[1], tets, 1e-6 * tets);
}

}  // namespace
}  // namespace pd
