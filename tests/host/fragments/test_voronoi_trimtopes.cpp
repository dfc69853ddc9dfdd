// Voronoi particles as trimtopes (render/voronoi_trimtopes.h): a Voronoi sphere renders without
// holes, rigid placement moves the hits with it, and a glass block of touching trimtopes bends a
// ray only at its outer faces.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "host/fragments/voronoi_trimtopes.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"
#include "render/camera.h"
#include "render/glass.h"
#include "render/renderer.h"
#include "render/traverse.h"

namespace pd {
namespace {

// Nearest crossing of the line with the mesh (brute force), or -1.
double mesh_hit(const TriMesh& m, const Ray& r) {
  double best = -1;
  const Vec3d o{r.o.x, r.o.y, r.o.z}, d{r.d.x, r.d.y, r.d.z};
  for (const Triangle& t : m.triangles) {
    const Vec3d& a = m.vertices[size_t(t[0])];
    const Vec3d e1 = m.vertices[size_t(t[1])] - a, e2 = m.vertices[size_t(t[2])] - a;
    const Vec3d h = cross(d, e2);
    const double det = dot(e1, h);
    if (det == 0) continue;
    const Vec3d s = o - a;
    const double u = dot(s, h) / det, v = dot(d, cross(s, e1)) / det, tt = dot(e2, cross(s, e1)) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && tt > 0 && (best < 0 || tt < best)) best = tt;
  }
  return best;
}

PrimitiveSet placed(const RestTrimtopes& rest, const Eigen::Matrix3d& rotation,
                    const Eigen::Vector3d& shift) {
  PrimitiveSet p;
  for (size_t i = 0; i < rest.size(); ++i) add_placed_trimtope(&p, rest, i, rotation, shift);
  return p;
}

struct HoleCount {
  int inside = 0, holes = 0, off = 0;
};

// Every pixel whose ray meets the sphere's mesh (and whose neighbours' rays do too, so pixels on
// the silhouette are left out) must hit a trimtope, at the mesh's distance.
HoleCount count_holes(const PrimitiveSet& prims, const TriMesh& mesh_world, const Camera& cam, int size) {
  const RenderScene scene = make_render_scene(prims, std::vector<Vec3>(size_t(prims.size()), {1, 1, 1}));
  const CameraFrame f = camera_frame(cam, size, size);
  HoleCount c;
  for (int y = 1; y + 1 < size; ++y)
    for (int x = 1; x + 1 < size; ++x) {
      const Ray r = camera_ray(f, real(x) + real(0.5), real(y) + real(0.5));
      const double tm = mesh_hit(mesh_world, r);
      if (tm < 0) continue;
      bool interior = true;
      for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}})
        interior = interior && mesh_hit(mesh_world, camera_ray(f, real(x + dx) + real(0.5),
                                                               real(y + dy) + real(0.5))) >= 0;
      if (!interior) continue;
      ++c.inside;
      const Hit h = traverse_short_stack<4>(scene.tree.view(), scene.prims.view(), r);
      if (h.prim < 0)
        ++c.holes;
      else if (std::fabs(h.t - tm) > 1e-4 * tm)
        ++c.off;
    }
  return c;
}

class VoronoiSphere : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mesh_ = new TriMesh(sphere_mesh(0.5, 0.08));
    geometry_ = new ParticleGeometry(voronoi_particles(*mesh_, 0.06, 7, 1000000, "sphere"));
    rest_ = new RestTrimtopes(rest_trimtopes(*geometry_));
  }
  static void TearDownTestSuite() {
    delete rest_;
    delete geometry_;
    delete mesh_;
  }
  static TriMesh* mesh_;
  static ParticleGeometry* geometry_;
  static RestTrimtopes* rest_;
};
TriMesh* VoronoiSphere::mesh_ = nullptr;
ParticleGeometry* VoronoiSphere::geometry_ = nullptr;
RestTrimtopes* VoronoiSphere::rest_ = nullptr;

TEST_F(VoronoiSphere, RestTrimtopesMatchTheCells) {
  ASSERT_EQ(rest_->size(), geometry_->size());
  int64_t surface_cells = 0;
  for (size_t i = 0; i < rest_->size(); ++i) {
    surface_cells += rest_->tri_start[i + 1] > rest_->tri_start[i];
    // The site lies inside its cell and inside its bounds.
    for (int64_t k = rest_->plane_start[i]; k < rest_->plane_start[i + 1]; ++k)
      EXPECT_LT(dot(rest_->plane_normal[size_t(k)], rest_->site[i]), rest_->plane_offset[size_t(k)]);
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(rest_->box[i].lo[a], rest_->site[i][a]);
      EXPECT_GE(rest_->box[i].hi[a], rest_->site[i][a]);
      // The solid part stays within the sphere's bounds.
      EXPECT_GE(rest_->box[i].lo[a], -0.5 - 1e-9);
      EXPECT_LE(rest_->box[i].hi[a], 0.5 + 1e-9);
    }
  }
  EXPECT_GT(surface_cells, int64_t(rest_->size()) / 4);
  EXPECT_LT(surface_cells, int64_t(rest_->size()));
}

TEST_F(VoronoiSphere, RendersWithoutHoles) {
  Camera cam;
  cam.eye = {real(0.4), real(0.6), real(2.2)};
  cam.look_at = {0, 0, 0};
  cam.vfov_degrees = 32;
  const HoleCount c =
      count_holes(placed(*rest_, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()), *mesh_, cam, 96);
  EXPECT_GT(c.inside, 3000);
  EXPECT_EQ(c.holes, 0);
  EXPECT_EQ(c.off, 0);  // the visible surface is the mesh
}

TEST_F(VoronoiSphere, RigidPlacementMovesTheWholeSolid) {
  // Rotated and moved as one fragment: the placed trimtopes still cover the moved mesh.
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(0.3, -0.2, 0.5);
  TriMesh moved = *mesh_;
  for (Vec3d& v : moved.vertices) {
    const Eigen::Vector3d q = rot * Eigen::Vector3d(v[0], v[1], v[2]) + shift;
    v = {q.x(), q.y(), q.z()};
  }
  Camera cam;
  cam.eye = {real(-1.2), real(0.9), real(2.4)};
  cam.look_at = {real(0.3), real(-0.2), real(0.5)};
  cam.vfov_degrees = 32;
  const HoleCount c = count_holes(placed(*rest_, rot, shift), moved, cam, 96);
  EXPECT_GT(c.inside, 3000);
  EXPECT_EQ(c.holes, 0);
  EXPECT_EQ(c.off, 0);
}

TEST_F(VoronoiSphere, RendersOnTheCpuRenderer) {
  // The renderer's image: the sphere covers the centre and is lit (not the sky's colour there).
  PrimitiveSet p = placed(*rest_, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  const RenderScene scene = make_render_scene(p, std::vector<Vec3>(size_t(p.size()), {real(0.7), 0, 0}));
  Camera cam;
  cam.eye = {0, 0, real(2.5)};
  cam.look_at = {0, 0, 0};
  RenderSettings s;
  s.width = s.height = 64;
  s.floor = false;
  const RenderResult r = make_renderer(false)->render_frame(scene, cam, s);
  const uint8_t* centre = &r.image.rgb[3 * (32 * 64 + 32)];
  EXPECT_GT(centre[0], 2 * centre[2]);  // red albedo
  const uint8_t* corner = &r.image.rgb[0];
  EXPECT_GT(corner[2], corner[0]);  // the sky
}

TEST(VoronoiGlass, BlockOfTouchingTrimtopesRefractsOnlyAtItsOuterFaces) {
  const TriMesh box = box_mesh({1, 0.4, 1});  // centred at the origin
  const ParticleGeometry g = voronoi_particles(box, 0.08, 3, 1000000, "block");
  const PrimitiveSet p = placed(rest_trimtopes(g), Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  const RenderScene scene = make_render_scene(p, std::vector<Vec3>(size_t(p.size()), {1, 1, 1}));
  const Vec3 d = normalize(Vec3{real(0.5), real(-0.8), real(0.2)});
  const Vec3 o = Vec3{real(-0.1), real(0.2), real(0.05)} - d;
  const Hit hit = traverse_full_stack(scene.tree.view(), scene.prims.view(), make_ray(o, d, 0, INFINITY));
  ASSERT_GE(hit.prim, 0);
  EXPECT_NEAR(hit.t, 1, 1e-5);
  const Fresnel f = fresnel_dielectric(-dot(d, hit.normal), 1, real(1.5));
  const GlassTransit out =
      glass_transit(scene.tree.view(), scene.prims.view(), o + hit.t * d,
                    refract(d, hit.normal, 1, real(1.5), f.cos_t), hit.prim, real(1.5), scene.join_gap);
  ASSERT_GE(out.last, 0);
  EXPECT_EQ(out.internal_reflections, 0);
  EXPECT_GE(out.elements, 4);
  EXPECT_NEAR(out.point.y, -0.2, 1e-5);  // the bottom face
  EXPECT_NEAR(out.dir.x, d.x, 2e-5);
  EXPECT_NEAR(out.dir.y, d.y, 2e-5);
  EXPECT_NEAR(out.dir.z, d.z, 2e-5);
}

}  // namespace
}  // namespace pd
