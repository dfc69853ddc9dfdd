// Mesh files: OBJ, PLY (ascii, binary) and STL (ascii, binary) round-trip a mesh exactly
// (STL binary to float precision); malformed files give a MeshError naming the file.
#include <gtest/gtest.h>

#include <algorithm>

#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

using test::ScratchDir;
using test::write_text;

// Same triangles over the same vertex positions (vertex order may differ after STL welding).
void expect_same_surface(const TriMesh& a, const TriMesh& b, double tol) {
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (size_t t = 0; t < a.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(a.vertices[a.triangles[t][c]][k], b.vertices[b.triangles[t][c]][k], tol) << t;
}

TEST(MeshIo, RoundTripsEveryFormat) {
  ScratchDir dir("io");
  const TriMesh torus = torus_mesh(0.3, 0.1, 0.05);
  write_obj(torus, dir.file("t.obj"));
  write_ply(torus, dir.file("a.ply"), false);
  write_ply(torus, dir.file("b.ply"), true);
  write_stl(torus, dir.file("a.stl"), false);
  write_stl(torus, dir.file("b.stl"), true);
  for (const char* name : {"t.obj", "a.ply", "b.ply", "a.stl"}) {
    SCOPED_TRACE(name);
    const TriMesh back = read_mesh(dir.file(name));
    EXPECT_EQ(back.vertices.size(), torus.vertices.size());
    expect_same_surface(torus, back, 0);
  }
  const TriMesh stl = read_mesh(dir.file("b.stl"));
  EXPECT_EQ(stl.vertices.size(), torus.vertices.size());
  expect_same_surface(torus, stl, 1e-7);
}

TEST(MeshIo, ObjPolygonsNegativeIndicesAndAttributes) {
  ScratchDir dir("obj");
  write_text(dir.file("q.obj"),
             "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
             "f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1\n");
  const TriMesh m = read_obj(dir.file("q.obj"));
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (Triangle{0, 2, 3}));
}

// Reads `text` as `name`, expecting a MeshError that names the file and contains `fragment`.
void expect_read_error(const std::string& name, const std::string& text, const std::string& fragment) {
  ScratchDir dir("bad");
  const std::string path = dir.file(name);
  write_text(path, text);
  try {
    read_mesh(path);
    ADD_FAILURE() << "no MeshError for " << name;
  } catch (const MeshError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.path(), path);
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    EXPECT_NE(msg.find("(allowed: "), std::string::npos) << msg;
  }
}

TEST(MeshIo, AFolderIsNoMesh) {
  ScratchDir dir("folder");
  const std::string path = dir.file("meshes.obj");
  std::filesystem::create_directories(path);
  try {
    read_mesh(path);
    ADD_FAILURE() << "a folder was read as a mesh";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder, not a mesh file"), std::string::npos) << e.what();
  }
}

TEST(MeshIo, MalformedFilesAreRefused) {
  expect_read_error("empty.obj", "", "empty");
  expect_read_error("nofaces.obj", "v 0 0 0\n", "no faces");
  expect_read_error("word.obj", "v 0 zero 0\n", "line 1: 'zero' is not a number");
  expect_read_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4: vertex index 4");
  expect_read_error("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3 vertices");
  expect_read_error("shape.xyz", "1 2 3", "unknown mesh format '.xyz'");
  expect_read_error("shape", "1 2 3", "has no file extension");
  expect_read_error("big.ply", "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n",
                    "binary_big_endian");
  expect_read_error(
      "short.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n",
      "ends early");
  expect_read_error("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float u\nend_header\n0\n",
                    "lacks x, y or z");
  expect_read_error(
      "strips.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
      "only triangle strips (a tristrips element), which are not read");
  expect_read_error("minus.ply",
                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n",
                    "face 0: vertex index -1 is out of range");
  expect_read_error("junk.stl", "not an stl file at all", "neither binary STL");
  expect_read_error(
      "partial.stl",
      "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n",
      "line 7: a facet of 2 vertices");
  expect_read_error("four.stl",
                    "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                    "vertex 1 1 0\nendloop\nendfacet\nendsolid x\n",
                    "line 9: a facet of 4 vertices");
  // An ascii STL cut between facets (no endsolid) was read as a mesh with a hole.
  expect_read_error("cut.stl",
                    "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                    "vertex 0 1 0\nendloop\nendfacet\n",
                    "the file ends before its 'endsolid' line");
}

// A polygon with a corner on the edge between two others (a T junction): split from a corner
// where every triangle has area (a fan from its first corner made one of zero area, refused).
TEST(MeshIo, APolygonWithACornerOnAnEdgeGetsNoFlatTriangle) {
  ScratchDir dir("tjunction");
  write_text(dir.file("t.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0 0\nf 1 4 3 2 5\n");
  const TriMesh m = read_mesh(dir.file("t.obj"));
  ASSERT_EQ(m.triangles.size(), 3u);
  double area = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    EXPECT_GT(triangle_area(m, t), 0.1) << t;
    area += triangle_area(m, t);
  }
  EXPECT_DOUBLE_EQ(area, 1.0);
  write_text(dir.file("t.ply"),
             "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 0\n5 0 3 2 1 4\n");
  const TriMesh ply = read_mesh(dir.file("t.ply"));
  ASSERT_EQ(ply.triangles.size(), 3u);
  for (size_t t = 0; t < 3; ++t) EXPECT_GT(triangle_area(ply, t), 0.1) << t;
}

// What editors and other exporters write: a UTF-8 byte-order mark, upper-case STL keywords, a
// comment after a face, lines ending in CR alone; and vertices no face uses, which are left out
// (a stray one set the bounds that place the body).
TEST(MeshIo, EditorsMarksCommentsLineEndsAndStrayVertices) {
  ScratchDir dir("editors");
  const std::string mark = "\xEF\xBB\xBF";
  const std::string tetra_obj =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2 # base\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  write_text(dir.file("mark.obj"), mark + tetra_obj);
  EXPECT_EQ(read_mesh(dir.file("mark.obj")).triangles.size(), 4u);
  std::string cr = tetra_obj;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  write_text(dir.file("cr.obj"), cr);
  EXPECT_EQ(read_mesh(dir.file("cr.obj")).triangles.size(), 4u);
  write_text(dir.file("stray.obj"), "v 100 100 100\n" + tetra_obj.substr(0, 32) + "v 2 2 2\n" +
                                        "f 2 4 3\nf 2 3 5\nf 2 5 4\nf 3 4 5\n");
  const TriMesh stray = read_mesh(dir.file("stray.obj"));
  ASSERT_EQ(stray.vertices.size(), 4u);
  EXPECT_EQ(bounds(stray).hi, (Vec3d{1, 1, 1}));
  EXPECT_EQ(stray.triangles[0], (Triangle{0, 2, 1}));
  const std::string facet =
      "FACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\n";
  write_text(dir.file("upper.stl"), mark + "SOLID X\n" + facet + "ENDSOLID X\n");
  EXPECT_EQ(read_mesh(dir.file("upper.stl")).triangles.size(), 1u);
  write_text(dir.file("mark.ply"), mark +
                                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 1\n"
                                       "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
                                       "0 1 0\n3 0 1 2\n");
  EXPECT_EQ(read_mesh(dir.file("mark.ply")).triangles.size(), 1u);
}

TEST(MeshIo, MissingFileNamesTheReason) {
  try {
    read_mesh("/nonexistent/perifrac/x.obj");
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/perifrac/x.obj: cannot read mesh file: No such file or directory");
  }
}

TEST(MeshIo, ReadsTheSharedMeshes) {
  PD_REQUIRE_SHARED_MESH(spot, "spot.obj");
  const TriMesh m = read_mesh(spot);
  EXPECT_EQ(m.triangles.size(), 5856u);
  EXPECT_EQ(m.vertices.size(), 2930u);
}

}  // namespace
}  // namespace pd
