// The crack mesh files: OBJ and PLY read back as written, and open in generic mesh readers.
#include "host/fragments/crack_mesh_file.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "host/io/atomic_file.h"
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
  for (size_t f = 0; f < s.triangles.size(); ++f) s.particle.push_back(int32_t(7 * f + 3));
  write_crack_obj(path("m.obj"), s, "frame 1");
  write_crack_ply(path("m.ply"), s, "frame 1");
  for (const char* name : {"m.obj", "m.ply"}) {
    SCOPED_TRACE(name);
    const CrackSurface back = read_crack_mesh(path(name));
    EXPECT_EQ(back.triangles, s.triangles);
    EXPECT_EQ(back.crack, s.crack);
    // The owning particles: in the PLY file only.
    EXPECT_EQ(back.particle, std::string(name) == "m.ply" ? s.particle : std::vector<int32_t>());
    ASSERT_EQ(back.vertices.size(), s.vertices.size());
    for (size_t v = 0; v < s.vertices.size(); ++v) EXPECT_LT(norm(back.vertices[v] - s.vertices[v]), 1e-7);
    // Generic mesh readers (as other tools read them) see the same triangles.
    EXPECT_EQ(read_mesh(path(name)).triangles.size(), s.triangles.size());
  }
  EXPECT_EQ(crack_mesh_file_name(42, "ply"), "crack_mesh_00042.ply");
  EXPECT_THROW(read_crack_mesh(path("m.obj") + ".ply"), MeshError);
}

// A vertex that is not finite is damage, in either format.
TEST_F(CrackMeshFile, VerticesThatAreNotFiniteAreRefused) {
  CrackSurface s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, std::numeric_limits<double>::quiet_NaN(), 0}};
  s.triangles = {{0, 1, 2}};
  s.crack = {0};
  s.particle = {0};
  write_crack_obj(path("nan.obj"), s, "frame 0");
  write_crack_ply(path("nan.ply"), s, "frame 0");
  EXPECT_THROW(read_crack_mesh(path("nan.obj")), MeshError);
  EXPECT_THROW(read_crack_mesh(path("nan.ply")), MeshError);
}

// PLY files written before the faces named their particles (14-byte face records) still read, with
// no owners; a file without owners is written with -1 for each face.
TEST_F(CrackMeshFile, PlyWithoutParticlesReadsWithNoOwners) {
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\ncomment perifrac crack mesh: frame 0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty uchar crack\nend_header\n";
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  bytes.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  const int32_t tri[3] = {0, 1, 2};
  bytes += char(3);
  bytes.append(reinterpret_cast<const char*>(tri), sizeof tri);
  bytes += char(1);
  write_file_atomic(path("old.ply"), bytes);
  const CrackSurface old = read_crack_mesh(path("old.ply"));
  ASSERT_EQ(old.triangles.size(), 1u);
  EXPECT_EQ(old.crack, std::vector<uint8_t>{1});
  EXPECT_TRUE(old.particle.empty());
  // Written again (no owners): -1 per face.
  write_crack_ply(path("again.ply"), old, "frame 0");
  EXPECT_EQ(read_crack_mesh(path("again.ply")).particle, std::vector<int32_t>{-1});
  // Owners that do not match the triangles are refused.
  CrackSurface bad = old;
  bad.particle = {1, 2};
  EXPECT_THROW(write_crack_ply(path("bad.ply"), bad, "frame 0"), std::invalid_argument);
  // A truncated body is refused.
  write_file_atomic(path("short.ply"), bytes.substr(0, bytes.size() - 1));
  EXPECT_THROW(read_crack_mesh(path("short.ply")), MeshError);
  // Counts whose byte sizes wrap around 2^64 to the body's length (12 nv + 14 nf = 2^64 k + body)
  // are refused, not read: nf = 2^62 + 1, and nv the solution of 12 nv = body - 14 nf mod 2^64
  // (divisible by 4; 0xAAAAAAAAAAAAAAAB is the inverse of 3 mod 2^64).
  const size_t body = bytes.size() - (bytes.find("end_header\n") + 11);
  const size_t nf = (size_t(1) << 62) + 1, x = body - 14 * nf;
  ASSERT_EQ(x % 4, 0u);
  const size_t nv = (x / 4) * size_t(0xAAAAAAAAAAAAAAABull);
  ASSERT_EQ(size_t(12 * nv + 14 * nf), body);  // wraps to the body's length
  std::string wrapped = bytes;
  wrapped.replace(wrapped.find("element vertex 3"), 16, "element vertex " + std::to_string(nv));
  wrapped.replace(wrapped.find("element face 1"), 14, "element face " + std::to_string(nf));
  write_file_atomic(path("wrapped.ply"), wrapped);
  EXPECT_THROW(read_crack_mesh(path("wrapped.ply")), MeshError);
}

}  // namespace
}  // namespace pd
