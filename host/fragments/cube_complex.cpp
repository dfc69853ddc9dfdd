#include "host/fragments/cube_complex.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace pd {

namespace {

using LatticeCell = std::array<int32_t, 3>;

// Lattice coordinates of every cube, found by walking face neighbours from one cube of each
// connected region (so jittered or float-rounded rest positions still get exact integers), and
// the neighbour across each face (face 2a + 1 is the +a side, 2a the -a side; -1: none).
struct Lattice {
  std::vector<int32_t> region;  // first particle of the region (its cube is at cell 0 0 0)
  std::vector<LatticeCell> cell;
  std::vector<std::array<int32_t, 6>> face;
};

Lattice walk_lattice(const ElementAdjacency& adj, const std::vector<Vec3>& rest,
                     const std::vector<int32_t>& cubes) {
  const size_t n = rest.size();
  Lattice g;
  g.region.assign(n, -1);
  g.cell.assign(n, LatticeCell{0, 0, 0});
  g.face.assign(n, {-1, -1, -1, -1, -1, -1});
  std::vector<uint8_t> is_cube(n, 0);
  for (int32_t p : cubes) {
    if (p < 0 || size_t(p) >= n)
      throw std::invalid_argument("cube_complex: particle " + std::to_string(p) + " out of range");
    is_cube[size_t(p)] = 1;
  }
  std::vector<int32_t> queue;
  for (int32_t start : cubes) {
    const size_t s = size_t(start);
    if (g.region[s] >= 0) continue;
    g.region[s] = int32_t(s);
    queue.assign(1, int32_t(s));
    for (size_t head = 0; head < queue.size(); ++head) {
      const int32_t i = queue[head];
      for (int64_t e = adj.offset[size_t(i)]; e < adj.offset[size_t(i) + 1]; ++e) {
        const int32_t j = adj.neighbor[size_t(e)];
        if (!is_cube[size_t(j)])
          throw std::invalid_argument("particle " + std::to_string(i) + " is a cube, its neighbour " +
                                      std::to_string(j) + " is not");
        // The face that j lies across: the dominant axis of the rest offset.
        const Vec3 d = rest[size_t(j)] - rest[size_t(i)];
        const double ad[3] = {std::abs(d.x), std::abs(d.y), std::abs(d.z)};
        const int a = ad[0] >= ad[1] && ad[0] >= ad[2] ? 0 : (ad[1] >= ad[2] ? 1 : 2);
        const bool up = (a == 0 ? d.x : a == 1 ? d.y : d.z) > 0;
        LatticeCell expected = g.cell[size_t(i)];
        expected[size_t(a)] += up ? 1 : -1;
        int32_t& slot = g.face[size_t(i)][size_t(2 * a + (up ? 1 : 0))];
        if (slot >= 0 && slot != j)
          throw std::invalid_argument("particles " + std::to_string(slot) + " and " + std::to_string(j) +
                                      " are both adjacent to particle " + std::to_string(i) +
                                      " across one cube face: not a cube grid");
        slot = j;
        if (g.region[size_t(j)] < 0) {
          g.region[size_t(j)] = g.region[size_t(i)];
          g.cell[size_t(j)] = expected;
          queue.push_back(j);
        } else if (g.cell[size_t(j)] != expected) {
          throw std::invalid_argument("the adjacency of particles " + std::to_string(i) + " and " +
                                      std::to_string(j) + " does not fit a cube grid");
        }
      }
    }
  }
  return g;
}

// Corners: cube i's corner b (bits x y z) is at lattice point cell + bits. Corners with the same
// region and lattice point are one corner, placed at the mean of the cubes' own corners.
struct Corners {
  std::vector<int32_t> of_cube;  // 8 per cube of the list: corner number
  std::vector<Vec3d> position;
};

Corners merge_corners(const Lattice& g, const std::vector<Vec3>& rest, const std::vector<real>& spacing,
                      const std::vector<int32_t>& cubes) {
  const size_t n = cubes.size();
  // Key of corner e = 8 k + b of cube k: region, then the lattice point, each coordinate offset to
  // be unsigned; sorting the 8n keys brings equal corners together.
  struct Key {
    uint64_t high, low;  // region | x, y | z
    int64_t e;
    bool operator<(const Key& o) const { return high != o.high ? high < o.high : low < o.low; }
    bool same(const Key& o) const { return high == o.high && low == o.low; }
  };
  auto biased = [](int32_t v) { return uint64_t(uint32_t(v) ^ 0x80000000u); };
  std::vector<Key> keys(8 * n);
  for (size_t e = 0; e < keys.size(); ++e) {
    const size_t i = size_t(cubes[e / 8]), b = e % 8;
    const LatticeCell& c = g.cell[i];
    keys[e] = {uint64_t(uint32_t(g.region[i])) << 32 | biased(c[0] + int32_t(b & 1)),
               biased(c[1] + int32_t((b >> 1) & 1)) << 32 | biased(c[2] + int32_t((b >> 2) & 1)), int64_t(e)};
  }
  std::sort(keys.begin(), keys.end());
  // Equal keys are one corner at the mean of the cubes' own corners.
  Corners out;
  out.of_cube.resize(8 * n);
  for (size_t at = 0; at < keys.size();) {
    size_t end = at;
    Vec3d sum{0, 0, 0};
    for (; end < keys.size() && keys[end].same(keys[at]); ++end) {
      const size_t e = size_t(keys[end].e), i = size_t(cubes[e / 8]), b = e % 8;
      const double h = 0.5 * double(spacing[i]);
      sum = sum + Vec3d{double(rest[i].x) + (b & 1 ? h : -h), double(rest[i].y) + ((b >> 1) & 1 ? h : -h),
                        double(rest[i].z) + ((b >> 2) & 1 ? h : -h)};
      out.of_cube[e] = int32_t(out.position.size());
    }
    out.position.push_back((1.0 / double(end - at)) * sum);
    at = end;
  }
  return out;
}

// Corner bits of face 2a + up, counter-clockwise seen from outside: the face spans the two other
// axes b = a+1, c = a+2 (cyclic); e_b x e_c = e_a, so (0,0) (1,0) (1,1) (0,1) in (b, c) faces +a.
std::array<int, 4> face_corners(int a, bool up) {
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const int base = up ? 1 << a : 0;
  const int bc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::array<int, 4> out{};
  for (int k = 0; k < 4; ++k) {
    const int* uv = bc[up ? k : (4 - k) % 4];
    out[size_t(k)] = base | (uv[0] << b) | (uv[1] << c);
  }
  return out;
}

}  // namespace

ElementComplex cube_complex(const ElementAdjacency& adjacency, const std::vector<Vec3>& rest,
                            const std::vector<real>& spacing, const std::vector<int32_t>& cubes) {
  if (adjacency.size() != rest.size() || spacing.size() != rest.size())
    throw std::invalid_argument("cube_complex: adjacency, rest positions and spacings differ in length");
  const Lattice g = walk_lattice(adjacency, rest, cubes);
  Corners corners = merge_corners(g, rest, spacing, cubes);

  // Each cube: its 8 corners, then its 6 faces, bordering the cube across each (or nothing).
  ElementComplex c;
  c.vertices = std::move(corners.position);
  for (size_t k = 0; k < cubes.size(); ++k) {
    const size_t i = size_t(cubes[k]);
    c.begin_element(int32_t(i));
    const int32_t first = int32_t(c.corner_vertex.size());
    for (size_t b = 0; b < 8; ++b) c.add_corner(corners.of_cube[8 * k + b]);
    for (int f = 0; f < 6; ++f) {
      const std::array<int, 4> bits = face_corners(f / 2, f % 2 == 1);
      const int32_t quad[4] = {first + bits[0], first + bits[1], first + bits[2], first + bits[3]};
      c.add_face(quad, 4, g.face[i][size_t(f)]);
    }
  }
  return c;
}

}  // namespace pd
