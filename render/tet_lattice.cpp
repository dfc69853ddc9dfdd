#include "render/tet_lattice.h"

#include <vector>

namespace pd {

namespace {

// A deterministic generator (PCG-style LCG) for the vertex jitter.
struct Lcg {
  uint64_t state = 0x853c49e6748fea9bull;
  double next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) * 0x1p-53;
  }
};

}  // namespace

void add_tet_lattice(PrimitiveSet* prims, int64_t nx, int64_t ny, int64_t nz, double h, double jitter) {
  Lcg rng;
  const int64_t vx = nx + 1, vy = ny + 1, vz = nz + 1;
  std::vector<Vec3> v(size_t(vx * vy * vz));
  for (int64_t k = 0; k < vz; ++k)
    for (int64_t j = 0; j < vy; ++j)
      for (int64_t i = 0; i < vx; ++i) {
        const double dx = jitter * h * (2 * rng.next() - 1), dy = jitter * h * (2 * rng.next() - 1),
                     dz = jitter * h * (2 * rng.next() - 1);
        v[size_t((k * vy + j) * vx + i)] = {real((double(i) - 0.5 * double(nx)) * h + dx),
                                            real(double(j) * h + dy),
                                            real((double(k) - 0.5 * double(nz)) * h + dz)};
      }
  // Kuhn's triangulation: the six monotone paths from corner 0 to corner 7 (corner bits x, y, z).
  const int paths[6][2] = {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}};
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        auto at = [&](int c) {
          return v[size_t(((k + (c >> 2 & 1)) * vy + j + (c >> 1 & 1)) * vx + i + (c & 1))];
        };
        for (const auto& p : paths) prims->add_tet(at(0), at(p[0]), at(p[0] | p[1]), at(7));
      }
}

}  // namespace pd
