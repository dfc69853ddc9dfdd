#include "render/hidden_tets.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstring>
#include <parallel/algorithm>

#include "render/shading.h"

namespace pd {

namespace {

// FNV-1a over the bit patterns of `count` points.
uint64_t points_hash(const Vec3* p, int count) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (int i = 0; i < count; ++i) {
    const float c[3] = {float(p[i].x), float(p[i].y), float(p[i].z)};
    uint32_t w[3];
    std::memcpy(w, c, sizeof c);
    for (uint32_t x : w) h = (h ^ x) * 0x100000001b3ull;
  }
  return h;
}

// The three vertices of face f in stored order (add_tet sorts a tetrahedron's vertices, so a
// face has the same vertices in the same order in both of its tetrahedra).
std::array<Vec3, 3> face_points(const Vec3* v, int f) {
  std::array<Vec3, 3> p;
  tet_face(v, f, &p[0], &p[1], &p[2]);
  return p;
}

bool same_points(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  return std::memcmp(a.data(), b.data(), sizeof a) == 0;
}

// Does `w` lie strictly on the other side of face f of tetrahedron v than v[f] does? (A face
// shared by two tetrahedra covers it only when they lie on its two sides; a duplicate does not.)
bool opposite_sides(const Vec3* v, int f, Vec3 w) {
  const std::array<Vec3, 3> p = face_points(v, f);
  const Eigen::Vector3d a(p[0].x, p[0].y, p[0].z), b(p[1].x, p[1].y, p[1].z), c(p[2].x, p[2].y, p[2].z);
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double own = n.dot(Eigen::Vector3d(v[f].x, v[f].y, v[f].z) - a);
  const double other = n.dot(Eigen::Vector3d(w.x, w.y, w.z) - a);
  return own * other < 0;
}

}  // namespace

std::vector<uint8_t> find_hidden_tets(const PrimitiveSet& prims, const std::vector<uint8_t>& material,
                                      int max_skin_vertices) {
  const int64_t n = prims.size();
  std::vector<uint8_t> hidden(size_t(n), 0);
  auto is_opaque_tet = [&](int64_t i) {
    return prims.kind[size_t(i)] == kPrimTet && (material.empty() || material[size_t(i)] == kMaterialOpaque);
  };
  auto vertices_of = [&](int64_t i) { return prims.tet_vertex.data() + 4 * size_t(prims.slot[size_t(i)]); };
  // Every face of every opaque tetrahedron (id = 4 primitive + face), sorted by the hash of its
  // points; other primitives get the largest hash and are never looked at.
  struct Face {
    uint64_t hash;
    int64_t id;
    bool operator<(const Face& o) const { return hash != o.hash ? hash < o.hash : id < o.id; }
  };
  constexpr uint64_t kNone = ~uint64_t(0);
  std::vector<Face> faces(size_t(4 * n));
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < n; ++i)
    for (int f = 0; f < 4; ++f)
      faces[size_t(4 * i + f)] = {
          is_opaque_tet(i) ? points_hash(face_points(vertices_of(i), f).data(), 3) : kNone, 4 * i + f};
  __gnu_parallel::sort(faces.begin(), faces.end());
  while (!faces.empty() && faces.back().hash == kNone) faces.pop_back();
  // A face is covered when another tetrahedron has the same points (compared in full among the
  // faces of equal hash) and lies on its other side. `covered`: a bit per face.
  std::vector<uint8_t> covered(size_t(n), 0);
  const int64_t m = int64_t(faces.size());
#pragma omp parallel for schedule(dynamic, 4096)
  for (int64_t a = 0; a < m; ++a) {
    const int64_t pa = faces[size_t(a)].id / 4, fa = faces[size_t(a)].id % 4;
    int64_t lo = a, hi = a + 1;
    while (lo > 0 && faces[size_t(lo - 1)].hash == faces[size_t(a)].hash) --lo;
    while (hi < m && faces[size_t(hi)].hash == faces[size_t(a)].hash) ++hi;
    if (hi - lo < 2) continue;
    const std::array<Vec3, 3> ka = face_points(vertices_of(pa), int(fa));
    for (int64_t b = lo; b < hi; ++b) {
      const int64_t pb = faces[size_t(b)].id / 4, fb = faces[size_t(b)].id % 4;
      if (pb == pa || !same_points(face_points(vertices_of(pb), int(fb)), ka) ||
          !opposite_sides(vertices_of(pa), int(fa), vertices_of(pb)[fb]))
        continue;
#pragma omp atomic
      covered[size_t(pa)] |= uint8_t(1u << fa);
      break;
    }
  }
  // The skin: the vertices of uncovered faces, as point hashes (a collision can only keep a
  // tetrahedron that could have been hidden).
  std::vector<uint64_t> skin;
  for (const Face& f : faces)
    if (!(covered[size_t(f.id / 4)] >> (f.id % 4) & 1))
      for (const Vec3& p : face_points(vertices_of(f.id / 4), int(f.id % 4)))
        skin.push_back(points_hash(&p, 1));
  __gnu_parallel::sort(skin.begin(), skin.end());
  skin.erase(std::unique(skin.begin(), skin.end()), skin.end());
  // Hidden: four covered faces and at most max_skin_vertices vertices on the skin.
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < n; ++i) {
    if (covered[size_t(i)] != 15) continue;
    const Vec3* v = vertices_of(i);
    int on_skin = 0;
    for (int c = 0; c < 4; ++c)
      on_skin += std::binary_search(skin.begin(), skin.end(), points_hash(v + c, 1));
    hidden[size_t(i)] = on_skin <= max_skin_vertices;
  }
  return hidden;
}

}  // namespace pd
