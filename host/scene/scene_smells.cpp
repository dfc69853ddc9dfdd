#include "host/scene/scene_smells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>
#include <utility>

namespace pd {

namespace {

// A body's particle bounding box.
struct Box {
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  void add(const Vec3& x) {
    const double c[3] = {x.x, x.y, x.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  bool overlaps(const Box& o, double margin) const {
    for (int a = 0; a < 3; ++a)
      if (lo[a] > o.hi[a] + margin || o.lo[a] > hi[a] + margin) return false;
    return true;
  }
  bool contains(const Vec3& x, double margin) const {
    const double c[3] = {x.x, x.y, x.z};
    for (int a = 0; a < 3; ++a)
      if (c[a] < lo[a] - margin || c[a] > hi[a] + margin) return false;
    return true;
  }
};

// Particles of two bodies whose centres are closer than a quarter of their two sizes (V^(1/3))
// summed: half a spacing, where bodies that merely touch keep a whole spacing. Per pair of bodies
// (a < b), the particles of the pair that overlap. Only particles where the bodies' boxes meet are
// hashed, so bodies apart cost one box test.
std::map<std::pair<int32_t, int32_t>, int64_t> overlapping_particles(const ParticleSet& ps, size_t bodies) {
  std::map<std::pair<int32_t, int32_t>, int64_t> overlaps;
  if (bodies < 2) return overlaps;
  std::vector<Box> box(bodies);
  double size_max = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    box[size_t(ps.body[i])].add(ps.rest[i]);
    size_max = std::max(size_max, std::cbrt(double(ps.volume[i])));
  }
  const double reach = 0.5 * size_max;  // the largest overlap distance
  // Particles inside another body's box: the only candidates.
  std::vector<int32_t> candidates;
  for (size_t i = 0; i < ps.size(); ++i)
    for (size_t b = 0; b < bodies; ++b)
      if (int32_t(b) != ps.body[i] && box[b].contains(ps.rest[i], reach)) {
        candidates.push_back(int32_t(i));
        break;
      }
  if (candidates.empty() || reach <= 0) return overlaps;
  const auto cell_of = [&](const Vec3& x) {
    return std::array<int64_t, 3>{int64_t(std::floor(x.x / reach)), int64_t(std::floor(x.y / reach)),
                                  int64_t(std::floor(x.z / reach))};
  };
  const auto key = [](const std::array<int64_t, 3>& c) {
    return uint64_t(c[0] * 73856093) ^ uint64_t(c[1] * 19349663) ^ uint64_t(c[2] * 83492791);
  };
  std::unordered_map<uint64_t, std::vector<int32_t>> grid;
  for (int32_t i : candidates) grid[key(cell_of(ps.rest[size_t(i)]))].push_back(i);
  std::vector<char> counted(ps.size(), 0);
  for (int32_t i : candidates) {
    const Vec3& x = ps.rest[size_t(i)];
    const std::array<int64_t, 3> c = cell_of(x);
    const double si = std::cbrt(double(ps.volume[size_t(i)]));
    for (int64_t dx = -1; dx <= 1 && !counted[size_t(i)]; ++dx)
      for (int64_t dy = -1; dy <= 1 && !counted[size_t(i)]; ++dy)
        for (int64_t dz = -1; dz <= 1 && !counted[size_t(i)]; ++dz) {
          const auto it = grid.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == grid.end()) continue;
          for (int32_t j : it->second) {
            if (ps.body[size_t(j)] == ps.body[size_t(i)]) continue;
            const Vec3& y = ps.rest[size_t(j)];
            const double d = std::sqrt(double(x.x - y.x) * (x.x - y.x) + double(x.y - y.y) * (x.y - y.y) +
                                       double(x.z - y.z) * (x.z - y.z));
            if (d < 0.25 * (si + std::cbrt(double(ps.volume[size_t(j)])))) {
              counted[size_t(i)] = 1;
              ++overlaps[std::minmax(ps.body[size_t(i)], ps.body[size_t(j)])];
              break;
            }
          }
        }
  }
  return overlaps;
}

}  // namespace

std::vector<std::string> scene_smells(const Scene& scene, const SimulationInput& in,
                                      const std::vector<std::string>& body_names) {
  std::vector<std::string> out;
  char line[512];
  const ParticleSet& ps = in.particles;
  // Anchors that hold nothing.
  std::vector<int64_t> held(scene.anchors.size(), 0);
  for (size_t i = 0; i < ps.size(); ++i)
    if ((ps.flags[i] & kAnchored) && ps.anchor[i] < held.size()) ++held[ps.anchor[i]];
  for (size_t g = 0; g < held.size(); ++g)
    if (held[g] == 0) {
      const std::string whose =
          scene.anchors[g].body.empty() ? "" : " of body '" + scene.anchors[g].body + "'";
      std::snprintf(line, sizeof line,
                    "warning: anchors[%zu]: its box holds no particle%s, so it does nothing", g,
                    whose.c_str());
      out.push_back(line);
    }
  // Bodies of one name: an anchor, crack or region naming it takes all of them.
  for (size_t a = 0; a < scene.bodies.size(); ++a)
    for (size_t b = a + 1; b < scene.bodies.size(); ++b)
      if (scene.bodies[a].name == scene.bodies[b].name) {
        std::snprintf(line, sizeof line,
                      "warning: bodies[%zu] and bodies[%zu] are both named '%s': an anchor, crack or region "
                      "naming it takes both",
                      a, b, scene.bodies[a].name.c_str());
        out.push_back(line);
      }
  // Particles whose centre starts below the floor: thrown up at the first step.
  if (scene.floor) {
    std::vector<int64_t> below(body_names.size(), 0);
    for (size_t i = 0; i < ps.size(); ++i)
      if (double(ps.rest[i].y) < scene.floor_height) ++below[size_t(ps.body[i])];
    for (size_t b = 0; b < below.size(); ++b)
      if (below[b] > 0) {
        std::snprintf(line, sizeof line,
                      "warning: body '%s': %lld particles start below the floor (y = %g), which throws them "
                      "up at once",
                      body_names[b].c_str(), (long long)below[b], scene.floor_height);
        out.push_back(line);
      }
  }
  // Bodies placed into each other: contact pushes them apart at the first step.
  for (const auto& [pair, count] : overlapping_particles(ps, body_names.size())) {
    std::snprintf(line, sizeof line,
                  "warning: bodies '%s' and '%s' overlap: %lld of their particles lie within half a spacing "
                  "of the other body's, and are pushed apart at the first step (which cracks a brittle "
                  "body); move them apart",
                  body_names[size_t(pair.first)].c_str(), body_names[size_t(pair.second)].c_str(),
                  (long long)count);
    out.push_back(line);
  }
  return out;
}

}  // namespace pd
