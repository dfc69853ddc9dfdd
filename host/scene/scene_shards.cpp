#include "host/scene/scene_shards.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "host/geometry/random.h"

namespace pd {

int64_t ShardSeeds::nearest(const std::array<double, 3>& x) const {
  std::array<int64_t, 3> c{};
  for (int a = 0; a < 3; ++a)
    c[size_t(a)] = std::clamp(int64_t(std::floor((x[size_t(a)] - origin[size_t(a)]) / size)), int64_t(0),
                              n[size_t(a)] - 1);
  int64_t best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int64_t k = std::max<int64_t>(c[2] - 2, 0); k <= std::min(c[2] + 2, n[2] - 1); ++k)
    for (int64_t j = std::max<int64_t>(c[1] - 2, 0); j <= std::min(c[1] + 2, n[1] - 1); ++j)
      for (int64_t i = std::max<int64_t>(c[0] - 2, 0); i <= std::min(c[0] + 2, n[0] - 1); ++i) {
        const int64_t id = (k * n[1] + j) * n[0] + i;
        const auto& s = seed[size_t(id)];
        const double d2 =
            (x[0] - s[0]) * (x[0] - s[0]) + (x[1] - s[1]) * (x[1] - s[1]) + (x[2] - s[2]) * (x[2] - s[2]);
        if (d2 < best_d2 || (d2 == best_d2 && id < best)) {
          best = id;
          best_d2 = d2;
        }
      }
  return best;
}

ShardSeeds shard_seeds(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double size,
                       double jitter, uint64_t seed) {
  ShardSeeds s;
  s.size = size;
  s.origin = lo;
  for (int a = 0; a < 3; ++a)
    s.n[size_t(a)] = std::max<int64_t>(1, int64_t(std::ceil((hi[size_t(a)] - lo[size_t(a)]) / size)));
  Random rng(seed);
  s.seed.reserve(size_t(s.n[0] * s.n[1] * s.n[2]));
  for (int64_t k = 0; k < s.n[2]; ++k)
    for (int64_t j = 0; j < s.n[1]; ++j)
      for (int64_t i = 0; i < s.n[0]; ++i) {
        const int64_t c[3] = {i, j, k};
        std::array<double, 3> p{};
        for (int a = 0; a < 3; ++a)
          p[size_t(a)] = lo[size_t(a)] + (double(c[a]) + 0.5 + jitter * (rng.uniform() - 0.5)) * size;
        s.seed.push_back(p);
      }
  return s;
}

uint16_t copy_material_entry(const Scene& scene, const std::string& key, const std::string& part,
                             MaterialTable& materials, uint16_t material) {
  if (materials.count >= kMaxMaterials)
    throw SceneError(scene.path, key,
                     part + " needs a material table entry of its own, and the scene has " +
                         std::to_string(kMaxMaterials) + " already (allowed: at most " +
                         std::to_string(kMaxMaterials) + " bodies, shards zones and dust holds together)");
  const uint16_t copy = uint16_t(materials.count++);
  materials.m[copy] = materials.m[material];
  return copy;
}

uint8_t shard_strength_byte(double hold) {
  return uint8_t(std::clamp(std::lround(255.0 / hold), 1L, 254L));
}

std::vector<int64_t> number_cells(const Scene& scene, size_t table, size_t body, const ParticleSet& ps,
                                  const std::vector<size_t>& members, int64_t& next) {
  const SceneShards& g = scene.shards[table];
  std::array<double, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (size_t i : members) {
    const double x[3] = {ps.rest[i].x, ps.rest[i].y, ps.rest[i].z};
    for (int a = 0; a < 3; ++a) {
      lo[size_t(a)] = std::min(lo[size_t(a)], x[a]);
      hi[size_t(a)] = std::max(hi[size_t(a)], x[a]);
    }
  }
  double cells = 1;
  for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil((hi[size_t(a)] - lo[size_t(a)]) / g.size));
  if (cells > double(kMaxShardCells))
    throw SceneError(scene.path, "shards[" + std::to_string(table) + "].size",
                     format_number(g.size) + " m cuts body '" + scene.bodies[body].name + "' into " +
                         std::to_string(int64_t(cells)) + " cells; allowed: at most " +
                         std::to_string(kMaxShardCells) + " (a larger size)");
  const ShardSeeds seeds = shard_seeds(lo, hi, g.size, g.jitter, scene.seed * 7919u + table * 104729u + body);
  std::vector<int64_t> number(seeds.seed.size(), -1), cell;
  cell.reserve(members.size());
  for (size_t i : members) {
    const int64_t s = seeds.nearest({ps.rest[i].x, ps.rest[i].y, ps.rest[i].z});
    if (number[size_t(s)] < 0) number[size_t(s)] = next++;
    cell.push_back(number[size_t(s)]);
  }
  return cell;
}

ShardReport assign_shards(const Scene& scene, ParticleSet& ps, MaterialTable& materials) {
  ShardReport report;
  ps.shard.clear();
  ps.shard_strength.clear();
  if (scene.shards.empty()) return report;
  ps.shard.assign(ps.size(), -1);
  ps.shard_strength.assign(ps.size(), uint8_t(255));
  for (size_t t = 0; t < scene.shards.size(); ++t) {
    const SceneShards& g = scene.shards[t];
    if (!g.pattern.empty()) continue;  // host/app/shards_pattern.h
    const std::string key = "shards[" + std::to_string(t) + "]";
    // The bonds between cells keep their limit exactly: the strength is a byte k / 255, and the
    // limits inside are raised by 255 / k, the nearest such factor to `hold`.
    const uint8_t strength = shard_strength_byte(g.hold);
    const double hold = 255.0 / double(strength);
    auto in_zone = [&](size_t i) {
      if (!g.radius) return true;
      const double d[3] = {ps.rest[i].x - g.center[0], ps.rest[i].y - g.center[1],
                           ps.rest[i].z - g.center[2]};
      return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= *g.radius * *g.radius;
    };
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      if (!g.body.empty() && scene.bodies[b].name != g.body) continue;
      // The body's particles in the zone.
      std::vector<size_t> mine;
      size_t in_body = 0;
      for (size_t i = 0; i < ps.size(); ++i) {
        if (ps.body[i] != int32_t(b)) continue;
        ++in_body;
        if (in_zone(i)) mine.push_back(i);
      }
      if (mine.empty()) continue;
      const std::vector<int64_t> cell = number_cells(scene, t, b, ps, mine, report.cells);
      // The compression strengthening is the material's (one table entry per body): raised in
      // place where the whole body is in cells, else on a copy the zone's particles take.
      const uint16_t material = ps.material[mine.front()];
      uint16_t zone_material = material;
      if (mine.size() < in_body) {
        zone_material = copy_material_entry(
            scene, key + ".radius", "the zone of body '" + scene.bodies[b].name + "'", materials, material);
        report.zone_materials.push_back({material, zone_material});
      }
      materials.m[zone_material].compression_alpha *= real(hold);
      for (size_t m = 0; m < mine.size(); ++m) {
        const size_t i = mine[m];
        ps.shard[i] = int32_t(cell[m]);
        ps.shard_strength[i] = strength;
        ps.strain_limit0[i] = real(double(ps.strain_limit0[i]) * hold);
        ps.material[i] = zone_material;
      }
      report.particles += int64_t(mine.size());
    }
  }
  if (report.particles == 0) {  // only patterns, or cells that hold no particle: the fields stay empty
    ps.shard.clear();
    ps.shard_strength.clear();
  }
  return report;
}

}  // namespace pd
