// The element complex: parts assembled into particle order, the structure checks, element volumes.
#include "host/fragments/element_complex.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pd {
namespace {

// A unit tetrahedron for particle p, its faces outward, bordering `other` across its first face.
ElementComplex unit_tet(int32_t p, int32_t other) {
  ElementComplex c;
  c.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  c.begin_element(p);
  for (int32_t v = 0; v < 4; ++v) c.add_corner(v);
  const int32_t faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (int k = 0; k < 4; ++k) c.add_face(faces[k], 3, k == 0 ? other : -1);
  return c;
}

TEST(ElementComplex, AssembleOrdersElementsByParticle) {
  const ElementComplex c = assemble(2, {unit_tet(1, 0), unit_tet(0, 1)});
  check(c, 2);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.particle, (std::vector<int32_t>{0, 1}));
  EXPECT_EQ(c.vertices.size(), 8u);
  // Particle 0's element came from the second part: its vertices are 4..7, its corners 0..3.
  EXPECT_EQ(c.corner_vertex[0], 4);
  EXPECT_EQ(c.face_corner[0], 1);
  EXPECT_EQ(c.face_other[0], 1);
  for (size_t e = 0; e < 2; ++e) EXPECT_DOUBLE_EQ(element_volume(c, e), 1.0 / 6);
}

TEST(ElementComplex, RefusesMissingAndDoubledParticlesAndBrokenStructure) {
  EXPECT_THROW(assemble(2, {unit_tet(0, -1)}), std::invalid_argument);
  EXPECT_THROW(assemble(1, {unit_tet(0, -1), unit_tet(0, -1)}), std::invalid_argument);
  EXPECT_THROW(assemble(1, {unit_tet(3, -1)}), std::invalid_argument);
  ElementComplex c = unit_tet(0, -1);
  check(c, 1);
  c.face_other[1] = 5;
  EXPECT_THROW(check(c, 1), std::invalid_argument);
  c = unit_tet(0, -1);
  c.corner_vertex[1] = 0;  // the same vertex twice
  EXPECT_THROW(check(c, 1), std::invalid_argument);
  c = unit_tet(0, -1);
  c.face_corner_start[1] = 2;  // a face of two corners
  EXPECT_THROW(check(c, 1), std::invalid_argument);
}

}  // namespace
}  // namespace pd
