// The crack mesh files: OBJ and PLY read back as written, and open in generic mesh readers.
#include "host/fragments/crack_mesh_file.h"

#include <gtest/gtest.h>

#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "tests/host/fragments/fragment_fixtures.h"

namespace pd {
namespace {

using CrackMeshFile = testing::TempDirTest;

TEST_F(CrackMeshFile, ObjAndPlyRoundTrip) {
  // A box's surface, its +x side flagged as crack (surface triangles first, as the mesh gives them).
  const TriMesh box = box_mesh({0.1, 0.2, 0.3});
  CrackSurface s;
  s.vertices = box.vertices;
  for (uint8_t crack = 0; crack < 2; ++crack)
    for (const Triangle& t : box.triangles) {
      bool plus_x = true;
      for (int32_t v : t) plus_x = plus_x && box.vertices[size_t(v)][0] > 0;
      if (plus_x != bool(crack)) continue;
      s.triangles.push_back(t);
      s.crack.push_back(crack);
    }
  ASSERT_EQ(s.crack_count(), 2u);
  write_crack_obj(path("m.obj"), s, "frame 1");
  write_crack_ply(path("m.ply"), s, "frame 1");
  for (const char* name : {"m.obj", "m.ply"}) {
    SCOPED_TRACE(name);
    const CrackSurface back = read_crack_mesh(path(name));
    EXPECT_EQ(back.triangles, s.triangles);
    EXPECT_EQ(back.crack, s.crack);
    ASSERT_EQ(back.vertices.size(), s.vertices.size());
    for (size_t v = 0; v < s.vertices.size(); ++v) EXPECT_LT(norm(back.vertices[v] - s.vertices[v]), 1e-7);
    // Generic mesh readers (as other tools read them) see the same triangles.
    EXPECT_EQ(read_mesh(path(name)).triangles.size(), s.triangles.size());
  }
  EXPECT_EQ(crack_mesh_file_name(42, "ply"), "crack_mesh_00042.ply");
  EXPECT_THROW(read_crack_mesh(path("m.obj") + ".ply"), MeshError);
}

}  // namespace
}  // namespace pd
