#include "host/fragments/tet_complex.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace pd {

namespace {

// Corners of the face opposite corner k of a positively oriented tet, counter-clockwise seen from
// outside the tet.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

double orientation(const std::vector<Vec3d>& x, const std::array<int32_t, 4>& t) {
  return dot(cross(x[size_t(t[1])] - x[size_t(t[0])], x[size_t(t[2])] - x[size_t(t[0])]),
             x[size_t(t[3])] - x[size_t(t[0])]);
}

}  // namespace

void EmbeddedTets::append(const TetMesh& mesh, int32_t first_particle) {
  const int32_t base = int32_t(vertices.size());
  vertices.insert(vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    tets.push_back({base + c[0], base + c[1], base + c[2], base + c[3]});
    particle.push_back(first_particle + int32_t(t));
  }
}

ElementComplex tet_complex(const EmbeddedTets& m) {
  const size_t nt = m.tets.size(), nv = m.vertices.size();
  if (m.particle.size() != nt)
    throw std::invalid_argument("tet_complex: " + std::to_string(nt) + " tets and " +
                                std::to_string(m.particle.size()) + " particles");
  // Tets: indices in range, corners 2 and 3 swapped where the orientation is negative so that
  // kFace gives outward triangles.
  std::vector<std::array<int32_t, 4>> tet = m.tets;
  for (size_t t = 0; t < nt; ++t) {
    for (int32_t v : tet[t])
      if (v < 0 || size_t(v) >= nv)
        throw std::invalid_argument("tet " + std::to_string(t) + " has vertex " + std::to_string(v) +
                                    " (allowed: 0.." + std::to_string(nv) + ")");
    if (orientation(m.vertices, tet[t]) < 0) std::swap(tet[t][2], tet[t][3]);
  }

  // Face neighbours: each tet face keyed by its sorted vertex triple; equal keys pair up. A key
  // found once is on the surface, more than twice is not a tet mesh.
  struct Entry {
    std::array<int32_t, 3> key;
    int64_t corner;  // 4 t + k: the face opposite corner k of tet t
    bool operator<(const Entry& o) const { return key != o.key ? key < o.key : corner < o.corner; }
  };
  std::vector<Entry> entry(4 * nt);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      Entry& e = entry[4 * t + size_t(k)];
      for (int i = 0; i < 3; ++i) e.key[size_t(i)] = tet[t][size_t(kFace[k][i])];
      std::sort(e.key.begin(), e.key.end());
      e.corner = int64_t(4 * t) + k;
    }
  std::sort(entry.begin(), entry.end());
  std::vector<int32_t> across(4 * nt, -1);  // per face: the particle of the tet across
  for (size_t i = 0; i < entry.size();) {
    size_t j = i + 1;
    while (j < entry.size() && entry[j].key == entry[i].key) ++j;
    if (j - i > 2)
      throw std::invalid_argument("a face is shared by " + std::to_string(j - i) + " tets (allowed: 2)");
    if (j - i == 2) {
      const int64_t a = entry[i].corner, b = entry[i + 1].corner;
      const int32_t pa = m.particle[size_t(a / 4)], pb = m.particle[size_t(b / 4)];
      if (pa == pb)
        throw std::invalid_argument("tets " + std::to_string(a / 4) + " and " + std::to_string(b / 4) +
                                    " share a face and stand for the same particle");
      across[size_t(a)] = pb;
      across[size_t(b)] = pa;
    }
    i = j;
  }

  ElementComplex c;
  c.vertices = m.vertices;
  for (size_t t = 0; t < nt; ++t) {
    c.begin_element(m.particle[t]);
    const int32_t first = int32_t(c.corner_vertex.size());
    for (int32_t v : tet[t]) c.add_corner(v);
    for (int k = 0; k < 4; ++k) {
      const int32_t tri[3] = {first + kFace[k][0], first + kFace[k][1], first + kFace[k][2]};
      c.add_face(tri, 3, across[4 * t + size_t(k)]);
    }
  }
  return c;
}

}  // namespace pd
