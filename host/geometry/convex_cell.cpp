#include "convex_cell.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pd {

ConvexCell::ConvexCell(const Vec3d& lo, const Vec3d& hi) {
  for (int k = 0; k < 8; ++k)
    vertices_.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  // Sides as corner quads (bit 0 = +x, bit 1 = +y, bit 2 = +z), counter-clockwise from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (int s = 0; s < 6; ++s) {
    const int axis = s / 2, high = s % 2;
    Vec3d n{0, 0, 0};
    n[axis] = high ? 1 : -1;
    faces_.push_back(
        {n, high ? hi[axis] : -lo[axis], -1 - s, {quads[s][0], quads[s][1], quads[s][2], quads[s][3]}});
  }
  update_live();
}

bool ConvexCell::clip(const Vec3d& n_in, double d_in, int32_t id) {
  const double len = norm(n_in);
  const Vec3d n = (1 / len) * n_in;
  const double d = d_in / len;
  // Signed distances of the corners in use; nothing to do when none is outside.
  side_.resize(vertices_.size());
  bool outside = false, inside = false;
  for (int32_t v : live_) {
    side_[size_t(v)] = dot(n, vertices_[size_t(v)]) - d;
    (side_[size_t(v)] > 0 ? outside : inside) = true;
  }
  if (!outside) return false;
  if (!inside) {
    faces_.clear();
    live_.clear();
    return true;
  }

  // Each face keeps its inside part; the crossing X of an edge leaving the half-space and Y of
  // the edge entering it are linked Y -> X for the new face (the opposite of the face's X -> Y).
  // (Small linear tables: a cut crosses a handful of edges.)
  std::vector<std::pair<uint64_t, int32_t>> crossing;
  auto cross_point = [&](int32_t a, int32_t b) {
    const uint64_t key = (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
    for (const auto& [k, v] : crossing)
      if (k == key) return v;
    const double sa = side_[size_t(a)], sb = side_[size_t(b)];
    const double t = sa / (sa - sb);
    vertices_.push_back(vertices_[size_t(a)] + t * (vertices_[size_t(b)] - vertices_[size_t(a)]));
    crossing.emplace_back(key, int32_t(vertices_.size() - 1));
    return int32_t(vertices_.size() - 1);
  };
  std::vector<std::pair<int32_t, int32_t>> cap_next;
  kept_.clear();
  for (Face& f : faces_) {
    std::vector<int32_t>& corners = scratch_corners_;
    corners.clear();
    int32_t exit = -1, entry = -1;
    const size_t m = f.corners.size();
    for (size_t k = 0; k < m; ++k) {
      const int32_t a = f.corners[k], b = f.corners[(k + 1) % m];
      const bool a_in = side_[size_t(a)] <= 0, b_in = side_[size_t(b)] <= 0;
      if (a_in) corners.push_back(a);
      if (a_in && !b_in) corners.push_back(exit = cross_point(a, b));
      if (!a_in && b_in) corners.push_back(entry = cross_point(a, b));
    }
    if (exit >= 0 && entry >= 0) cap_next.emplace_back(entry, exit);
    if (corners.size() >= 3) {
      f.corners.swap(corners);  // the old corner buffer becomes the next face's scratch
      kept_.push_back(std::move(f));
    }
  }
  // The new face: follow the links from any crossing.
  Face cap{n, d, id, {}};
  if (!cap_next.empty()) {
    const int32_t start = cap_next.front().first;
    int32_t v = start;
    do {
      cap.corners.push_back(v);
      const auto it =
          std::find_if(cap_next.begin(), cap_next.end(), [&](const auto& e) { return e.first == v; });
      if (it == cap_next.end()) break;
      v = it->second;
    } while (v != start && cap.corners.size() <= cap_next.size());
  }
  if (cap.corners.size() >= 3) kept_.push_back(std::move(cap));
  faces_.swap(kept_);
  update_live();
  return true;
}

void ConvexCell::update_live() {
  live_.clear();
  for (const Face& f : faces_) live_.insert(live_.end(), f.corners.begin(), f.corners.end());
  std::sort(live_.begin(), live_.end());
  live_.erase(std::unique(live_.begin(), live_.end()), live_.end());
}

double ConvexCell::max_distance(const Vec3d& p) const {
  double best = 0;
  for (int32_t v : live_) best = std::max(best, distance2(p, vertices_[size_t(v)]));
  return std::sqrt(best);
}

double ConvexCell::volume(const Vec3d& inner) const {
  double six_v = 0;
  for (const Face& f : faces_) {
    const Vec3d a = vertices_[size_t(f.corners[0])] - inner;
    for (size_t k = 1; k + 1 < f.corners.size(); ++k)
      six_v +=
          dot(a, cross(vertices_[size_t(f.corners[k])] - inner, vertices_[size_t(f.corners[k + 1])] - inner));
  }
  return six_v / 6;
}

void ConvexCell::bounds(Vec3d& lo, Vec3d& hi) const {
  Box3d box;
  for (const Face& f : faces_)
    for (int32_t v : f.corners) box.add(vertices_[size_t(v)]);
  lo = box.lo;
  hi = box.hi;
}

}  // namespace pd
