// The crack mesh as render triangles (host/app/mesh_surface.h): normals per surface with a crease
// angle, Taubin smoothing of the crack surface only, the particles a mesh covers and the triangles'
// looks.
#include "host/app/mesh_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "host/geometry/shapes.h"
#include "render/shading.h"

namespace pd {
namespace {

void expect_vec(const Vec3d& a, const Vec3d& b, double tol = 1e-12) {
  EXPECT_NEAR(a[0], b[0], tol);
  EXPECT_NEAR(a[1], b[1], tol);
  EXPECT_NEAR(a[2], b[2], tol);
}

Vec3d unit(const Vec3d& a) {
  return (1 / norm(a)) * a;
}

// Two triangles sharing the edge (0,0,0)-(0,0,1), both facing +y, folded by the slope `h` on each
// side; the first on the original surface, the second flagged `second_crack`.
CrackSurface fold(double h, uint8_t second_crack) {
  CrackSurface s;
  s.vertices = {{0, 0, 0}, {0, 0, 1}, {1, -h, 0.5}, {-1, -h, 0.5}};
  s.triangles = {{0, 1, 2}, {1, 0, 3}};
  s.crack = {0, second_crack};
  s.particle = {0, 1};
  return s;
}

TEST(MeshSurface, VertexNormalsBlendWithinTheCreaseAngleOnOneSurfaceOnly) {
  // A 22.6 degree fold on one surface: the shared vertices take the mean normal, +y.
  const double h = 0.2;
  const auto both = corner_normals(fold(h, 0));
  for (int f = 0; f < 2; ++f)
    for (int c = 0; c < 2; ++c) expect_vec(both[size_t(f)][size_t(c)], {0, 1, 0});
  expect_vec(both[0][2], unit({h, 1, 0}));  // the far vertices keep their own face's normal
  expect_vec(both[1][2], unit({-h, 1, 0}));
  // The same fold where the second face is a crack: each side keeps its flat normal at the shared
  // vertices (the edge between surface and crack stays sharp).
  const auto split = corner_normals(fold(h, 1));
  for (int c = 0; c < 3; ++c) {
    expect_vec(split[0][size_t(c)], unit({h, 1, 0}));
    expect_vec(split[1][size_t(c)], unit({-h, 1, 0}));
  }
  // A 127 degree fold on one surface is a crease: flat normals again.
  const auto sharp = corner_normals(fold(2, 0));
  for (int c = 0; c < 3; ++c) {
    expect_vec(sharp[0][size_t(c)], unit({2, 1, 0}));
    expect_vec(sharp[1][size_t(c)], unit({-2, 1, 0}));
  }
}

TEST(MeshSurface, ABoxKeepsItsFlatFaces) {
  const TriMesh box = box_mesh({1, 2, 3});
  CrackSurface s;
  s.vertices = box.vertices;
  s.triangles = box.triangles;
  s.crack.assign(s.triangles.size(), 0);
  const auto n = corner_normals(s);
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    const auto& t = s.triangles[f];
    const Vec3d flat = unit(cross(s.vertices[size_t(t[1])] - s.vertices[size_t(t[0])],
                                  s.vertices[size_t(t[2])] - s.vertices[size_t(t[0])]));
    for (int c = 0; c < 3; ++c) expect_vec(n[f][size_t(c)], flat);
  }
}

// A square crack of m x m cells in the plane y = 0 whose inner vertices zig-zag by +-a in y (the
// element faces' staircase), its rim shared with original-surface triangles.
CrackSurface zigzag_crack(int m, double a) {
  CrackSurface s;
  auto id = [m](int i, int k) { return int32_t(k * (m + 1) + i); };
  for (int k = 0; k <= m; ++k)
    for (int i = 0; i <= m; ++i) {
      const bool rim = i == 0 || k == 0 || i == m || k == m;
      s.vertices.push_back({double(i), rim ? 0.0 : ((i + k) % 2 ? a : -a), double(k)});
    }
  // The original surface: one triangle on each rim edge, up to a vertex above the square.
  s.vertices.push_back({m / 2.0, 5, m / 2.0});
  const int32_t apex = int32_t(s.vertices.size() - 1);
  for (int i = 0; i < m; ++i) {
    for (const auto& [p, q] : {std::pair{id(i, 0), id(i + 1, 0)}, std::pair{id(i + 1, m), id(i, m)},
                               std::pair{id(0, i + 1), id(0, i)}, std::pair{id(m, i), id(m, i + 1)}}) {
      s.triangles.push_back({p, q, apex});
      s.crack.push_back(0);
    }
  }
  // The crack cells, two triangles each, facing -y.
  for (int k = 0; k < m; ++k)
    for (int i = 0; i < m; ++i) {
      s.triangles.push_back({id(i, k), id(i + 1, k), id(i + 1, k + 1)});
      s.triangles.push_back({id(i, k), id(i + 1, k + 1), id(i, k + 1)});
      s.crack.push_back(1);
      s.crack.push_back(1);
    }
  s.particle.assign(s.triangles.size(), 0);
  return s;
}

// Roughness of the crack surface: the mean angle [rad] between the normals of crack triangles
// that share an edge.
double crack_roughness(const CrackSurface& s) {
  std::vector<Vec3d> n(s.triangles.size());
  for (size_t f = 0; f < n.size(); ++f) {
    const auto& t = s.triangles[f];
    n[f] = unit(cross(s.vertices[size_t(t[1])] - s.vertices[size_t(t[0])],
                      s.vertices[size_t(t[2])] - s.vertices[size_t(t[0])]));
  }
  double sum = 0;
  int pairs = 0;
  for (size_t f = 0; f < n.size(); ++f)
    for (size_t g = f + 1; g < n.size(); ++g) {
      if (!s.crack[f] || !s.crack[g]) continue;
      int shared = 0;
      for (int32_t a : s.triangles[f])
        for (int32_t b : s.triangles[g]) shared += a == b;
      if (shared != 2) continue;
      sum += std::acos(std::min(1.0, dot(n[f], n[g])));
      ++pairs;
    }
  return sum / pairs;
}

TEST(MeshSurface, SmoothingFlattensTheZigZagAndKeepsTheOriginalSurface) {
  const CrackSurface before = zigzag_crack(8, 0.3);
  CrackSurface after = before;
  smooth_cracks(after, kDefaultCrackSmoothing);
  const double rough_before = crack_roughness(before), rough_after = crack_roughness(after);
  EXPECT_GT(rough_before, 0.3);
  EXPECT_LT(rough_after, 0.5 * rough_before);
  // Vertices on the original surface (the rim and the apex) stay bit for bit; the inner ones move
  // towards the plane without leaving the square.
  for (size_t v = 0; v < before.vertices.size(); ++v) {
    const Vec3d& p = before.vertices[v];
    const bool inner = v + 1 < before.vertices.size() && p[1] != 0;
    if (!inner) {
      EXPECT_EQ(after.vertices[v], p) << "vertex " << v;
      continue;
    }
    EXPECT_LT(std::fabs(after.vertices[v][1]), 0.5 * std::fabs(p[1])) << "vertex " << v;
    EXPECT_NEAR(after.vertices[v][0], p[0], 0.05);
    EXPECT_NEAR(after.vertices[v][2], p[2], 0.05);
  }
  // No passes: nothing moves; the triangles and flags are never touched.
  CrackSurface none = before;
  smooth_cracks(none, 0);
  EXPECT_EQ(none.vertices, before.vertices);
  EXPECT_EQ(after.triangles, before.triangles);
  EXPECT_EQ(after.crack, before.crack);
}

TEST(MeshSurface, SmoothingKeepsALargeScaleBend) {
  // Taubin's mu step undoes the lambda step's shrinking: a gentle bend of the crack (a long wave
  // over the square) keeps most of its height, while the zig-zag on top of it goes.
  CrackSurface s = zigzag_crack(16, 0.2);
  const size_t centre = size_t(8 * 17 + 8);
  for (size_t v = 0; v + 1 < s.vertices.size(); ++v) {
    Vec3d& p = s.vertices[v];
    p[1] += std::sin(M_PI * p[0] / 16) * std::sin(M_PI * p[2] / 16);
  }
  const double height = s.vertices[centre][1];
  ASSERT_NEAR(height, 0.8, 1e-12);  // the bend's top, on a zag of the zig-zag
  smooth_cracks(s, kDefaultCrackSmoothing);
  const double smoothed = s.vertices[centre][1];
  EXPECT_LT(std::fabs(smoothed - 1), 0.5 * std::fabs(height - 1));
  EXPECT_GT(smoothed, 0.9);
}

TEST(MeshSurface, CoveredParticlesAreTheBodiesInTheMesh) {
  CrackSurface s = fold(0.2, 1);
  s.particle = {0, 3};
  const std::vector<int32_t> body = {0, 0, 1, 2, 2, 1};
  EXPECT_EQ(covered_particles(s, body), (std::vector<uint8_t>{1, 1, 0, 1, 1, 0}));
  s.particle = {0, 6};
  EXPECT_THROW(covered_particles(s, body), std::invalid_argument);
  s.particle.clear();  // a file from before the owners were written
  try {
    covered_particles(s, body);
    FAIL() << "a mesh without owners was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("particle"), std::string::npos) << e.what();
  }
}

TEST(MeshSurface, TrianglesTakeTheirOwnersLook) {
  CrackSurface s = fold(0.2, 1);
  s.particle = {1, 0};
  PrimitiveSet prims;
  prims.add_cube({0, 0, 0}, 1);
  prims.add_cube({3, 0, 0}, 1);
  std::vector<Vec3> albedo = {{1, 0, 0}, {0, 1, 0}};
  std::vector<uint8_t> material = {kMaterialOpaque, kMaterialGlass};
  add_surface_triangles(s, corner_normals(s), &prims, &albedo, &material);
  ASSERT_EQ(prims.size(), 4);
  EXPECT_EQ(prims.kind[2], kPrimTriangle);
  EXPECT_EQ(prims.kind[3], kPrimTriangle);
  EXPECT_EQ(albedo[2].y, 1);  // particle 1's
  EXPECT_EQ(albedo[3].x, 1);  // particle 0's
  EXPECT_EQ(material,
            (std::vector<uint8_t>{kMaterialOpaque, kMaterialGlass, kMaterialGlass, kMaterialOpaque}));
  // The vertices as given, and the shading normals of corner_normals.
  EXPECT_EQ(prims.tri_vertex[2].x, 1);
  EXPECT_NEAR(prims.tri_normal[0].x, unit({0.2, 1, 0})[0], 1e-6);
  // No materials: none added.
  std::vector<uint8_t> opaque;
  add_surface_triangles(s, corner_normals(s), &prims, &albedo, &opaque);
  EXPECT_TRUE(opaque.empty());
  EXPECT_EQ(albedo.size(), 6u);
}

}  // namespace
}  // namespace pd
