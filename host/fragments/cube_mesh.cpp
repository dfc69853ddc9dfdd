#include "cube_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <ostream>
#include <stdexcept>

#include "../io/atomic_file.h"

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

Lattice walk_lattice(const ElementAdjacency& adj, const std::vector<Vec3>& rest) {
  const size_t n = rest.size();
  Lattice g;
  g.region.assign(n, -1);
  g.cell.assign(n, LatticeCell{0, 0, 0});
  g.face.assign(n, {-1, -1, -1, -1, -1, -1});
  std::vector<int32_t> queue;
  for (size_t s = 0; s < n; ++s) {
    if (g.region[s] >= 0) continue;
    g.region[s] = int32_t(s);
    queue.assign(1, int32_t(s));
    for (size_t head = 0; head < queue.size(); ++head) {
      const int32_t i = queue[head];
      for (int64_t e = adj.offset[size_t(i)]; e < adj.offset[size_t(i) + 1]; ++e) {
        const int32_t j = adj.neighbor[size_t(e)];
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
  std::vector<int32_t> of_cube;  // 8 per cube: corner number
  std::vector<Eigen::Vector3d> position;
};

Corners merge_corners(const Lattice& g, const std::vector<Vec3>& rest, const std::vector<real>& spacing) {
  const size_t n = rest.size();
  // Key of cube corner e = 8 i + b: region, then the lattice point, each coordinate offset to be
  // unsigned; sorting the 8n keys brings equal corners together.
  struct Key {
    uint64_t high, low;  // region | x, y | z
    int64_t e;
    bool operator<(const Key& o) const { return high != o.high ? high < o.high : low < o.low; }
    bool same(const Key& o) const { return high == o.high && low == o.low; }
  };
  auto biased = [](int32_t v) { return uint64_t(uint32_t(v) ^ 0x80000000u); };
  std::vector<Key> keys(8 * n);
  for (size_t e = 0; e < keys.size(); ++e) {
    const size_t i = e / 8, b = e % 8;
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
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (; end < keys.size() && keys[end].same(keys[at]); ++end) {
      const size_t e = size_t(keys[end].e), i = e / 8, b = e % 8;
      const double h = 0.5 * double(spacing[i]);
      sum += Eigen::Vector3d(rest[i].x, rest[i].y, rest[i].z) +
             Eigen::Vector3d(b & 1 ? h : -h, (b >> 1) & 1 ? h : -h, (b >> 2) & 1 ? h : -h);
      out.of_cube[e] = int32_t(out.position.size());
    }
    out.position.push_back(sum / double(end - at));
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

FragmentMesh cube_fragment_mesh(const ElementAdjacency& adjacency, const std::vector<Vec3>& rest,
                                const std::vector<real>& spacing, const Components& c) {
  const size_t n = rest.size();
  if (adjacency.size() != n || spacing.size() != n || c.id.size() != n)
    throw std::invalid_argument(
        "cube_fragment_mesh: adjacency, rest positions, spacings and components differ in length");
  const Lattice g = walk_lattice(adjacency, rest);
  const Corners corners = merge_corners(g, rest, spacing);

  // Each fragment: the faces of its cubes not shared with a cube of the same fragment, with the
  // corners renumbered per object in order of first use.
  FragmentMesh mesh;
  std::vector<int32_t> local(corners.position.size(), -1);
  std::vector<int32_t> used;
  for (size_t k = 0; k < c.count(); ++k) {
    for (int32_t m = c.start[k]; m < c.start[k + 1]; ++m) {
      const size_t i = size_t(c.members[size_t(m)]);
      for (int f = 0; f < 6; ++f) {
        const int32_t j = g.face[i][size_t(f)];
        if (j >= 0 && c.index[size_t(j)] == int32_t(k)) continue;
        std::array<int32_t, 4> quad{};
        const std::array<int, 4> bits = face_corners(f / 2, f % 2 == 1);
        for (int q = 0; q < 4; ++q) {
          const int32_t corner = corners.of_cube[8 * i + size_t(bits[size_t(q)])];
          if (local[size_t(corner)] < 0) {
            local[size_t(corner)] = int32_t(mesh.vertices.size());
            mesh.vertices.push_back(corners.position[size_t(corner)]);
            used.push_back(corner);
          }
          quad[size_t(q)] = local[size_t(corner)];
        }
        mesh.quads.push_back(quad);
      }
    }
    for (int32_t corner : used) local[size_t(corner)] = -1;
    used.clear();
    mesh.ids.push_back(c.component_id(k));
    mesh.vertex_start.push_back(int64_t(mesh.vertices.size()));
    mesh.quad_start.push_back(int64_t(mesh.quads.size()));
  }
  return mesh;
}

void write_obj(const std::string& path, const FragmentMesh& mesh) {
  write_file_atomic(path, [&](std::ostream& out) {
    out << "# perifrac fragment surfaces in rest space [m], one object per fragment;\n"
           "# fragments_NNNNN.pfg holds each fragment's transform per frame (docs/fragments.md)\n";
    char line[128];
    for (size_t o = 0; o < mesh.objects(); ++o) {
      out << "o fragment_" << mesh.ids[o] << "\n";
      for (int64_t v = mesh.vertex_start[o]; v < mesh.vertex_start[o + 1]; ++v) {
        const Eigen::Vector3d& p = mesh.vertices[size_t(v)];
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
        out << line;
      }
      for (int64_t q = mesh.quad_start[o]; q < mesh.quad_start[o + 1]; ++q) {
        const auto& f = mesh.quads[size_t(q)];
        std::snprintf(line, sizeof line, "f %d %d %d %d\n", f[0] + 1, f[1] + 1, f[2] + 1, f[3] + 1);
        out << line;
      }
    }
  });
}

}  // namespace pd
