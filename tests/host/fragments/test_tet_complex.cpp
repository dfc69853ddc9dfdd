// Tet elements: faces outward (negatively oriented tets turned), paired across shared faces;
// meshes that are not tet meshes are refused.
#include "host/fragments/tet_complex.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "tests/host/fragments/fragment_fixtures.h"

namespace pd {
namespace {

TEST(TetComplex, FacesPointOutAndPairUp) {
  EmbeddedTets box = testing::box_tets(3, 2, 2, 0.5);
  for (size_t t = 0; t < box.tets.size(); t += 2) std::swap(box.tets[t][0], box.tets[t][1]);  // half inverted
  const ElementComplex c = tet_complex(box);
  check(c, box.tets.size());
  size_t surface = 0;
  for (size_t e = 0; e < c.size(); ++e) {
    EXPECT_NEAR(element_volume(c, e), 0.125 / 6, 1e-15);
    for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f) {
      const int32_t o = c.face_other[size_t(f)];
      surface += o < 0;
      if (o < 0) continue;
      int back = 0;
      for (int64_t g = c.face_start[size_t(o)]; g < c.face_start[size_t(o) + 1]; ++g)
        back += c.face_other[size_t(g)] == int32_t(e);
      EXPECT_EQ(back, 1);
    }
  }
  EXPECT_EQ(surface, size_t(2 * 2 * (3 * 2 + 2 * 2 + 2 * 3)));  // two triangles per boundary square
}

TEST(TetComplex, RefusesWhatIsNotATetMesh) {
  EmbeddedTets m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {0, 1, 2, 4}, {0, 1, 2, 5}};  // one face of three tets
  m.particle = {0, 1, 2};
  EXPECT_THROW(tet_complex(m), std::invalid_argument);
  m.tets.pop_back();
  m.particle = {0, 0};  // two tets across a face standing for one particle
  EXPECT_THROW(tet_complex(m), std::invalid_argument);
  m.particle = {0, 1};
  m.tets[1][3] = 9;
  EXPECT_THROW(tet_complex(m), std::invalid_argument);
}

}  // namespace
}  // namespace pd
