#include "host/geometry/convex_cell.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pd {

ConvexCell::ConvexCell(const Vec3d& lo, const Vec3d& hi) {
  reset(lo, hi);
}

void ConvexCell::reset(const Vec3d& lo, const Vec3d& hi) {
  vertices_.clear();
  for (Face& f : faces_) spare_.push_back(std::move(f));
  faces_.clear();
  for (int k = 0; k < 8; ++k)
    vertices_.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  // Sides as corner quads (bit 0 = +x, bit 1 = +y, bit 2 = +z), counter-clockwise from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (int s = 0; s < 6; ++s) {
    const int axis = s / 2, high = s % 2;
    Vec3d n{0, 0, 0};
    n[axis] = high ? 1 : -1;
    faces_.push_back(new_face(n, high ? hi[axis] : -lo[axis], -1 - s));
    faces_.back().corners.assign(quads[s], quads[s] + 4);
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
    for (Face& f : faces_) spare_.push_back(std::move(f));
    faces_.clear();
    live_.clear();
    return true;
  }

  // Each face keeps its inside part; the crossing X of an edge leaving the half-space and Y of
  // the edge entering it are linked Y -> X for the new face (the opposite of the face's X -> Y).
  // (Small linear tables: a cut crosses a handful of edges.)
  std::vector<std::pair<uint64_t, int32_t>>& crossing = crossing_;
  crossing.clear();
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
  std::vector<std::pair<int32_t, int32_t>>& cap_next = cap_next_;
  cap_next.clear();
  kept_.clear();
  for (Face& f : faces_) {
    // A face with every corner inside stays as it is.
    bool cut = false;
    for (int32_t v : f.corners) cut = cut || side_[size_t(v)] > 0;
    if (!cut) {
      kept_.push_back(std::move(f));
      continue;
    }
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
    f.corners.swap(corners);  // the old corner buffer becomes the next face's scratch
    if (f.corners.size() >= 3)
      kept_.push_back(std::move(f));
    else
      spare_.push_back(std::move(f));
  }
  // The new face: follow the links from any crossing.
  Face cap = new_face(n, d, id);
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
  if (cap.corners.size() >= 3)
    kept_.push_back(std::move(cap));
  else
    spare_.push_back(std::move(cap));
  faces_.swap(kept_);
  update_live();
  return true;
}

ConvexCell::Face ConvexCell::new_face(const Vec3d& n, double d, int32_t id) {
  Face f;
  if (!spare_.empty()) {
    f = std::move(spare_.back());
    spare_.pop_back();
  }
  f.normal = n;
  f.offset = d;
  f.id = id;
  f.corners.clear();
  return f;
}

void ConvexCell::update_live() {
  // Each corner once, in the order the faces list them (no sort: marks by epoch).
  if (mark_.size() < vertices_.size()) mark_.resize(vertices_.size() + 64, 0);
  if (++epoch_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0);
    epoch_ = 1;
  }
  live_.clear();
  for (const Face& f : faces_)
    for (int32_t v : f.corners)
      if (mark_[size_t(v)] != epoch_) {
        mark_[size_t(v)] = epoch_;
        live_.push_back(v);
      }
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

void clip_polygon(std::vector<Vec3d>& poly, const Vec3d& n, double d, std::vector<Vec3d>& scratch) {
  scratch.clear();
  for (size_t k = 0; k < poly.size(); ++k) {
    const Vec3d& a = poly[k];
    const Vec3d& b = poly[(k + 1) % poly.size()];
    const double sa = dot(n, a) - d, sb = dot(n, b) - d;
    if (sa <= 0) scratch.push_back(a);
    if ((sa <= 0) != (sb <= 0)) scratch.push_back(a + (sa / (sa - sb)) * (b - a));
  }
  poly.swap(scratch);
}

}  // namespace pd
