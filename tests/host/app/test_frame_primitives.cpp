// A frame as primitives (render/frame_primitives.h): tets of tet bodies and cubes placed by their
// fragment's rigid transform (cubes turned: oriented cubes), axis-aligned without a rotation,
// moved by the displacement without fragments; a block of tetrahedra renders as one solid.
#include "host/app/frame_primitives.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "render/kdtree.h"
#include "render/traverse.h"

namespace pd {
namespace {

// A unit cube [0, s]^3 split into the 6 tetrahedra of Kuhn's triangulation around its diagonal.
EmbeddedTets kuhn_cube(double s, int32_t first_particle) {
  EmbeddedTets t;
  for (int c = 0; c < 8; ++c) t.vertices.push_back({(c & 1) * s, ((c >> 1) & 1) * s, ((c >> 2) & 1) * s});
  const int32_t paths[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for (int k = 0; k < 6; ++k) {
    const int32_t a = paths[k][0], b = a | paths[k][1];
    t.tets.push_back({0, a, b, 7});
    t.particle.push_back(first_particle + k);
  }
  return t;
}

// Particles 0..5: the cube's tets (rest position their barycentres), particle 6: a grid cube.
struct TetRun {
  RestData rest;
  FrameData frame;
  EmbeddedTets tets = kuhn_cube(0.1, 0);
};

TetRun make_run() {
  TetRun r;
  for (size_t k = 0; k < 6; ++k) {
    Vec3 c{0, 0, 0};
    for (int32_t v : r.tets.tets[k])
      c += real(0.25) * Vec3{real(r.tets.vertices[size_t(v)][0]), real(r.tets.vertices[size_t(v)][1]),
                             real(r.tets.vertices[size_t(v)][2])};
    r.rest.position.push_back(c);
    r.rest.volume.push_back(float(0.001 / 6));
  }
  r.rest.position.push_back({real(0.3), real(0.05), real(0.05)});
  r.rest.volume.push_back(float(0.001));
  r.rest.body = {0, 0, 0, 0, 0, 0, 1};
  r.rest.material.assign(7, 0);
  r.frame.position = r.rest.position;
  r.frame.damage.assign(7, 0.0f);
  r.frame.body = r.rest.body;
  r.frame.component.assign(7, 0);  // one fragment, id 0
  return r;
}

Eigen::Vector3d place(const Fragment& f, Vec3 p) {
  return f.rotation * Eigen::Vector3d(p.x, p.y, p.z) + f.translation;
}

TEST(FramePrimitives, TetsAndCubesFollowTheirFragmentsTransform) {
  TetRun r = make_run();
  FragmentsFrame fr;
  fr.fragments.resize(1);
  Fragment& f = fr.fragments[0];
  f.rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  f.translation = Eigen::Vector3d(0.2, -0.1, 0.05);
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  frame_primitives(r.rest, r.frame, &prims, &albedo, nullptr, &fr, &r.tets);
  ASSERT_EQ(prims.size(), 7);
  ASSERT_EQ(albedo.size(), 7u);
  // Each tetrahedron's vertices moved (stored in add_tet's order: matched by nearest).
  for (int32_t i = 0; i < 6; ++i) {
    ASSERT_EQ(prims.kind[size_t(i)], kPrimTet);
    for (int c = 0; c < 4; ++c) {
      const Vec3d& v = r.tets.vertices[size_t(r.tets.tets[size_t(i)][size_t(c)])];
      const Eigen::Vector3d e = place(f, {real(v[0]), real(v[1]), real(v[2])});
      double nearest = INFINITY;
      for (int k = 0; k < 4; ++k) {
        const Vec3 got = prims.tet_vertex[4 * size_t(prims.slot[size_t(i)]) + size_t(k)];
        nearest = std::min(nearest, (Eigen::Vector3d(got.x, got.y, got.z) - e).norm());
      }
      EXPECT_LT(nearest, 2e-6) << "tetrahedron " << i << " vertex " << c;
    }
  }
  // The grid cube: an oriented cube at the moved rest position, axes the rotation's columns.
  ASSERT_EQ(prims.kind[6], kPrimOrientedCube);
  const size_t s = size_t(prims.slot[6]);
  const Eigen::Vector3d c = place(f, r.rest.position[6]);
  EXPECT_NEAR(prims.ocube_center[s].x, c.x(), 1e-6);
  EXPECT_NEAR(prims.ocube_center[s].y, c.y(), 1e-6);
  EXPECT_NEAR(prims.ocube_center[s].z, c.z(), 1e-6);
  EXPECT_NEAR(prims.ocube_half[s], 0.05, 1e-6);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(prims.ocube_axis[3 * s + size_t(a)].x, f.rotation(0, a), 1e-6);
    EXPECT_NEAR(prims.ocube_axis[3 * s + size_t(a)].y, f.rotation(1, a), 1e-6);
    EXPECT_NEAR(prims.ocube_axis[3 * s + size_t(a)].z, f.rotation(2, a), 1e-6);
  }
}

TEST(FramePrimitives, UnrotatedFragmentsAndNoFragmentsGiveAxisAlignedCubes) {
  TetRun r = make_run();
  FragmentsFrame fr;
  fr.fragments.resize(1);
  fr.fragments[0].rotation(0, 1) = 1e-9;  // below float resolution: the identity
  fr.fragments[0].translation = Eigen::Vector3d(0, 0.5, 0);
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  frame_primitives(r.rest, r.frame, &prims, &albedo, nullptr, &fr, &r.tets);
  ASSERT_EQ(prims.kind[6], kPrimCube);
  EXPECT_NEAR(prims.cube_center[size_t(prims.slot[6])].y, 0.55, 1e-6);
  // Without fragments: the cube at the particle's position, each tet moved by its displacement.
  for (Vec3& p : r.frame.position) p.x += real(1);
  frame_primitives(r.rest, r.frame, &prims, &albedo, nullptr, nullptr, &r.tets);
  ASSERT_EQ(prims.kind[6], kPrimCube);
  EXPECT_NEAR(prims.cube_center[size_t(prims.slot[6])].x, 1.3, 1e-6);
  EXPECT_NEAR(prims.tet_vertex[4 * size_t(prims.slot[0])].x, 1, 1e-6);  // vertex 0 was at the origin
}

TEST(FramePrimitives, RejectsTetsOfParticlesTheRestFileLacks) {
  TetRun r = make_run();
  r.tets.particle[2] = 7;
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  EXPECT_THROW(frame_primitives(r.rest, r.frame, &prims, &albedo, nullptr, nullptr, &r.tets),
               std::invalid_argument);
}

// The six tets of the turned and moved cube leave no crack: rays aimed at its faces from outside
// all hit at the face's plane, and every face's normal is the cube's turned axis.
TEST(FramePrimitives, TurnedTetBlockRendersAsOneSolidCube) {
  TetRun r = make_run();
  r.rest.position[6] = r.frame.position[6] = {0, 5, 0};  // the grid cube out of the way
  FragmentsFrame fr;
  fr.fragments.resize(1);
  Fragment& f = fr.fragments[0];
  f.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  f.translation = Eigen::Vector3d(-0.3, 0.1, 0.2);
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  frame_primitives(r.rest, r.frame, &prims, &albedo, nullptr, &fr, &r.tets);
  const KdTree tree = build_kdtree(prims.bounds());
  const Eigen::Vector3d centre = place(f, {real(0.05), real(0.05), real(0.05)});
  int hits = 0;
  for (int a = 0; a < 3; ++a)
    for (int i = 1; i < 20; ++i)
      for (int j = 1; j < 20; ++j) {
        // Aim along -axis a at the point (u, v) of the face +a, from 1 m outside.
        Eigen::Vector3d local(0, 0, 0);
        local[a] = 0.05;
        local[(a + 1) % 3] = 0.1 * (i / 20.0 - 0.5);
        local[(a + 2) % 3] = 0.1 * (j / 20.0 - 0.5);
        const Eigen::Vector3d axis = f.rotation.col(a);
        const Eigen::Vector3d o = centre + f.rotation * local + axis;
        const Ray ray = make_ray({real(o.x()), real(o.y()), real(o.z())},
                                 {real(-axis.x()), real(-axis.y()), real(-axis.z())}, 0, INFINITY);
        const Hit h = traverse_full_stack(tree.view(), prims.view(), ray);
        ASSERT_GE(h.prim, 0) << "crack at face " << a << " (" << i << ", " << j << ")";
        EXPECT_LT(h.prim, 6);
        EXPECT_NEAR(h.t, 1, 2e-6);
        EXPECT_NEAR(h.normal.x, axis.x(), 1e-5);
        EXPECT_NEAR(h.normal.y, axis.y(), 1e-5);
        EXPECT_NEAR(h.normal.z, axis.z(), 1e-5);
        ++hits;
      }
  EXPECT_EQ(hits, 3 * 19 * 19);
}

}  // namespace
}  // namespace pd
