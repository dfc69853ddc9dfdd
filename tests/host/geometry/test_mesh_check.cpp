// Mesh checks: each broken mesh gets its own clear MeshError, repairs are reported, and the
// Stanford bunny (an open scan) is refused with its hole count or repaired on request.
#include <gtest/gtest.h>

#include <cmath>

#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/random.h"
#include "host/geometry/shapes.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

const std::string kPath = "broken.obj";

// A latitude-longitude sphere of radius 1: 21 segments around, 10 rings, a fan of 21 triangles
// around each pole (the first and the last triangles), so removing a fan opens one hole.
TriMesh latitude_longitude_sphere() {
  std::vector<std::array<double, 2>> profile;
  for (int k = 0; k <= 10; ++k) {
    const double a = 3.14159265358979323846 * k / 10;
    profile.push_back({k == 0 || k == 10 ? 0.0 : std::sin(a), -std::cos(a)});
  }
  TriMesh sphere = revolve(profile, 21, false);
  transform(sphere, 1, -1.0 * bounds(sphere).center());
  if (signed_volume(sphere) < 0) flip_orientation(sphere);
  return sphere;
}

TriMesh tetrahedron() {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// check_solid on `mesh` must throw a MeshError with `fragment`, the path and an "allowed" part.
void expect_refused(TriMesh mesh, const std::string& fragment, MeshCheckOptions options = {}) {
  try {
    check_solid(mesh, kPath, options);
    ADD_FAILURE() << "no MeshError; expected: " << fragment;
  } catch (const MeshError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(kPath + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    EXPECT_NE(msg.find("(allowed: "), std::string::npos) << msg;
  }
}

TEST(MeshCheck, AClosedMeshPasses) {
  TriMesh m = tetrahedron();
  const MeshReport r = check_solid(m, kPath, {});
  EXPECT_FALSE(r.flipped);
  EXPECT_EQ(r.holes, 0);
  EXPECT_NEAR(signed_volume(m), 1.0 / 6, 1e-15);
}

TEST(MeshCheck, EmptyMesh) {
  expect_refused(TriMesh{}, "empty");
}

TEST(MeshCheck, NonFiniteCoordinate) {
  TriMesh m = tetrahedron();
  m.vertices[2][1] = std::nan("");
  expect_refused(m, "vertex 2 (0-based) has a coordinate that is not a finite number");
  TriMesh far = tetrahedron();
  far.vertices[1][0] = 1e103;  // finite, but the volume would not be
  expect_refused(far, "vertex 1 (0-based) has a coordinate of 1e+103 (allowed: coordinates within 1e15");
}

TEST(MeshCheck, DegenerateTriangles) {
  TriMesh m = tetrahedron();
  m.triangles.push_back({1, 1, 2});
  expect_refused(m, "1 triangle is degenerate");
  TriMesh flat = tetrahedron();
  flat.vertices.push_back({0.5, 0.5, 0});  // on the edge 1-2: a zero-area sliver
  flat.triangles.push_back({1, 4, 2});
  expect_refused(flat, "triangle 4");
}

TEST(MeshCheck, NonManifoldEdge) {
  // Three triangles on the edge 0-1.
  TriMesh m = tetrahedron();
  m.vertices.push_back({0.5, -1, 0.5});
  m.triangles.push_back({0, 1, 4});
  expect_refused(m, "shared by more than two triangles (non-manifold");
}

TEST(MeshCheck, InconsistentOrientation) {
  TriMesh m = tetrahedron();
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  expect_refused(m, "inconsistent orientation");
}

TEST(MeshCheck, OpenMeshReportsTheHoleCount) {
  TriMesh box = box_mesh({1, 1, 1});
  box.triangles.erase(box.triangles.begin(), box.triangles.begin() + 2);  // the -x face
  expect_refused(box,
                 "the mesh is open: 1 hole (boundary loops) with 4 boundary edges (allowed: a closed mesh)");
  // The repair is offered only where the caller takes it (a body's mesh).
  expect_refused(box, "or repair = \"fill_holes\"", {false, true});
  // A sphere with two caps removed: two holes.
  TriMesh sphere = latitude_longitude_sphere();
  const size_t n = sphere.triangles.size();
  const int segments = 21;
  sphere.triangles.erase(sphere.triangles.end() - segments, sphere.triangles.end());
  sphere.triangles.erase(sphere.triangles.begin(), sphere.triangles.begin() + segments);
  ASSERT_EQ(sphere.triangles.size(), n - 2 * segments);
  expect_refused(sphere, "2 holes");
}

TEST(MeshCheck, FillHolesClosesSimpleLoops) {
  TriMesh sphere = latitude_longitude_sphere();
  const double closed_volume = signed_volume(sphere);
  sphere.triangles.erase(sphere.triangles.begin(), sphere.triangles.begin() + 21);  // bottom cap fan
  const MeshReport r = check_solid(sphere, kPath, {true});
  EXPECT_EQ(r.holes, 1);
  EXPECT_TRUE(boundary_loops(sphere, kPath).empty());
  // The patch is flat where the pole's cone was: a small loss of volume.
  EXPECT_NEAR(signed_volume(sphere), closed_volume, 2e-3 * closed_volume);
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes.back().find("filled 1 hole"), std::string::npos);
}

TEST(MeshCheck, NonSimpleHoleIsRefused) {
  // Two triangles touching at one vertex: the boundary passes vertex 0 twice.
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};
  expect_refused(m, "lies on two holes at once", {true});
  expect_refused(m, "(a non-simple boundary loop) (allowed: a closed mesh)");
  expect_refused(m, "simple boundary loops for repair = \"fill_holes\"", {true, true});
}

TEST(MeshCheck, InvertedOrientationIsFlipped) {
  TriMesh m = torus_mesh(1, 0.3, 0.1);
  const double volume = signed_volume(m);
  flip_orientation(m);
  const MeshReport r = check_solid(m, kPath, {});
  EXPECT_TRUE(r.flipped);
  EXPECT_NEAR(signed_volume(m), volume, 1e-12 * volume);
  EXPECT_NE(r.notes.back().find("flipped"), std::string::npos);
}

// Parts are oriented by how they nest (a part on its own faces out, one inside another into it),
// so that every fill reads a mesh of parts one way: a separate cube facing in made Voronoi cells
// of negative volume, a cube inside another facing out was hollow for grids and filled for tets.
TEST(MeshCheck, PartsAreOrientedByHowTheyNest) {
  auto moved = [](TriMesh m, double dx) {
    for (Vec3d& v : m.vertices) v[0] += dx;
    return m;
  };
  auto flipped = [](TriMesh m) {
    flip_orientation(m);
    return m;
  };
  auto checked = [](const TriMesh& m, int& notes) {
    TriMesh copy = m;
    const MeshReport r = check_solid(copy, "parts.obj", {});
    notes = int(r.notes.size());
    return signed_volume(copy);
  };
  int notes = 0;
  TriMesh apart = box_mesh({1, 1, 1});
  append(apart, flipped(moved(box_mesh({1, 1, 1}), 3)));  // a second cube facing in, beside it
  EXPECT_NEAR(checked(apart, notes), 2, 1e-12);           // was "encloses no volume"
  EXPECT_EQ(notes, 1);
  TriMesh nested = box_mesh({2, 2, 2});
  append(nested, box_mesh({1, 1, 1}));  // an inner cube facing out: a cavity
  EXPECT_NEAR(checked(nested, notes), 7, 1e-12);
  EXPECT_EQ(notes, 1);
  TriMesh hollow = box_mesh({2, 2, 2});
  append(hollow, flipped(box_mesh({1, 1, 1})));  // as it should be: nothing to say
  EXPECT_NEAR(checked(hollow, notes), 7, 1e-12);
  EXPECT_EQ(notes, 0);
  EXPECT_NEAR(checked(flipped(hollow), notes), 7, 1e-12);  // inside out as a whole: one flip
  EXPECT_EQ(notes, 1);
  TriMesh crossing = box_mesh({1, 1, 1});
  TriMesh into = box_mesh({1, 1, 1});
  for (Vec3d& v : into.vertices) v = v + Vec3d{0.53, 0.21, 0.17};
  append(crossing, into);  // modelled into each other: kept, their union, and said
  EXPECT_NEAR(checked(crossing, notes), 2, 1e-12);
  EXPECT_EQ(notes, 1);
  {
    TriMesh copy = crossing;
    EXPECT_EQ(
        check_solid(copy, "parts.obj", {}).notes.back().rfind("2 parts cross another: grid particles", 0),
        0u);
  }
  TriMesh cavity = box_mesh({0.1, 0.1, 0.1});  // in the two cubes' overlap: one level down, kept
  for (Vec3d& v : cavity.vertices) v = v + Vec3d{0.3, 0.1, 0.1};
  TriMesh with_cavity = crossing;
  append(with_cavity, flipped(cavity));
  EXPECT_NEAR(checked(with_cavity, notes), 2 - 1e-3, 1e-12);
  EXPECT_EQ(notes, 1);                          // (the crossing)
  TriMesh reversed_into = box_mesh({1, 1, 1});  // a part crossing another, facing in: turned out
  append(reversed_into, flipped(into));
  EXPECT_NEAR(checked(reversed_into, notes), 2, 1e-12);
  EXPECT_EQ(notes, 2);
}

// A cube whose triangles were exported apart, each corner a round-off from its copies: named as
// such (it was "open: 12 holes", and fill_holes then found no volume), and welded on request.
TEST(MeshCheck, FacesExportedApartAreNamedAndWeldedOnRequest) {
  const TriMesh cube = box_mesh({1, 1, 1});
  TriMesh apart;
  Random rng(5);
  for (const Triangle& t : cube.triangles) {
    Triangle own{};
    for (int c = 0; c < 3; ++c) {
      own[size_t(c)] = int32_t(apart.vertices.size());
      apart.vertices.push_back(cube.vertices[size_t(t[size_t(c)])] +
                               Vec3d{1e-9 * rng.uniform(), 1e-9 * rng.uniform(), 1e-9 * rng.uniform()});
    }
    apart.triangles.push_back(own);
  }
  TriMesh refused = apart;
  try {
    check_solid(refused, kPath, {false, true});
    ADD_FAILURE() << "accepted";
  } catch (const MeshError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("28 boundary vertices lie within 1e-6 of the mesh's size of another"), std::string::npos)
        << m;
    EXPECT_NE(m.find("repair = \"weld\""), std::string::npos) << m;
  }
  TriMesh welded = apart;
  const MeshReport r = check_solid(welded, kPath, {false, true, true});
  EXPECT_EQ(welded.vertices.size(), 8u);
  EXPECT_NEAR(signed_volume(welded), 1, 1e-8);
  EXPECT_EQ(r.notes.front(), "merged 28 vertices within 1e-6 of the mesh's size of another");
}

TEST(MeshCheck, IdenticalVerticesAreMerged) {
  // Each face with its own corners (as an OBJ with split seams): welded into a closed mesh.
  const TriMesh box = box_mesh({1, 2, 3});
  TriMesh split;
  for (const Triangle& t : box.triangles) {
    const int32_t base = int32_t(split.vertices.size());
    for (int32_t c : t) split.vertices.push_back(box.vertices[c]);
    split.triangles.push_back({base, base + 1, base + 2});
  }
  const MeshReport r = check_solid(split, kPath, {});
  EXPECT_EQ(split.vertices.size(), 8u);
  EXPECT_EQ(r.welded_vertices, 36 - 8);
  EXPECT_NEAR(signed_volume(split), 6, 1e-12);
}

// The bunny decision: the raw scan is refused with its hole count unless the scene asks for
// repair = "fill_holes", which closes its holes (all simple loops) by fan triangulation.
TEST(MeshCheck, StanfordBunnyIsRefusedOrRepaired) {
  PD_REQUIRE_SHARED_MESH(path, "stanford-bunny.obj");
  TriMesh bunny = read_mesh(path);
  try {
    TriMesh copy = bunny;
    check_solid(copy, path, {});
    FAIL() << "the open bunny was accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("the mesh is open: 5 holes"), std::string::npos) << e.what();
  }
  const MeshReport r = check_solid(bunny, path, {true});
  EXPECT_EQ(r.holes, 5);
  EXPECT_TRUE(boundary_loops(bunny, path).empty());
  EXPECT_GT(signed_volume(bunny), 0);
}

}  // namespace
}  // namespace pd
