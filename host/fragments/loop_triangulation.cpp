#include "host/fragments/loop_triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd {

namespace {

double orient(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Is p inside or on triangle (a, b, c), counter-clockwise?
bool in_triangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

// Is p inside the loop (even-odd rule)?
bool inside_loop(const Point2& p, const std::vector<int32_t>& loop, const std::vector<Point2>& pts) {
  bool in = false;
  for (size_t k = 0, j = loop.size() - 1; k < loop.size(); j = k++) {
    const Point2 &a = pts[size_t(loop[k])], &b = pts[size_t(loop[j])];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) in = !in;
  }
  return in;
}

// Do segments ab and cd cross at a point inside both (not at a shared end)?
bool segments_cross(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double d1 = orient(a, b, c), d2 = orient(a, b, d), d3 = orient(c, d, a), d4 = orient(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// Joins hole `h` into `outer` along a segment from the hole's rightmost vertex to the nearest outer
// vertex that it reaches without crossing an edge of any loop: outer .. o, h .. h, o .. outer.
void bridge(std::vector<int32_t>& outer, const std::vector<int32_t>& h,
            const std::vector<std::vector<int32_t>>& all, const std::vector<Point2>& pts) {
  size_t hk = 0;
  for (size_t k = 1; k < h.size(); ++k)
    if (pts[size_t(h[k])].x > pts[size_t(h[hk])].x) hk = k;
  const Point2& p = pts[size_t(h[hk])];
  std::vector<std::pair<double, size_t>> order;
  for (size_t k = 0; k < outer.size(); ++k) {
    const Point2& q = pts[size_t(outer[k])];
    order.emplace_back((q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y), k);
  }
  std::sort(order.begin(), order.end());
  size_t ok = order.front().second;
  for (const auto& [d2, k] : order) {
    const Point2& q = pts[size_t(outer[k])];
    bool clear = true;
    for (const auto& loop : all)
      for (size_t e = 0; e < loop.size() && clear; ++e)
        clear = !segments_cross(p, q, pts[size_t(loop[e])], pts[size_t(loop[(e + 1) % loop.size()])]);
    if (clear) {
      ok = k;
      break;
    }
  }
  std::vector<int32_t> joined(outer.begin(), outer.begin() + long(ok) + 1);
  for (size_t k = 0; k <= h.size(); ++k) joined.push_back(h[(hk + k) % h.size()]);
  joined.insert(joined.end(), outer.begin() + long(ok), outer.end());
  outer.swap(joined);
}

// Ear clipping of one counter-clockwise loop (which may touch itself along bridges).
void clip_ears(std::vector<int32_t> loop, const std::vector<Point2>& pts,
               std::vector<std::array<int32_t, 3>>& out) {
  while (loop.size() > 3) {
    const size_t n = loop.size();
    size_t best = n;
    double best_area = -std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < n; ++k) {
      const int32_t ia = loop[(k + n - 1) % n], ib = loop[k], ic = loop[(k + 1) % n];
      const Point2 &a = pts[size_t(ia)], &b = pts[size_t(ib)], &c = pts[size_t(ic)];
      const double area = orient(a, b, c);
      if (area > best_area) best = k, best_area = area;  // the fallback when no ear passes
      if (area <= 0) continue;
      bool ear = true;
      for (size_t j = 0; j < n && ear; ++j) {
        const int32_t iv = loop[j];
        if (iv == ia || iv == ib || iv == ic) continue;
        const Point2& v = pts[size_t(iv)];
        if ((v.x == a.x && v.y == a.y) || (v.x == b.x && v.y == b.y) || (v.x == c.x && v.y == c.y)) continue;
        ear = !in_triangle(v, a, b, c);
      }
      if (ear) {
        best = k;
        break;
      }
    }
    out.push_back({loop[(best + n - 1) % n], loop[best], loop[(best + 1) % n]});
    loop.erase(loop.begin() + long(best));
  }
  if (loop.size() == 3) out.push_back({loop[0], loop[1], loop[2]});
}

}  // namespace

double twice_area(const std::vector<int32_t>& loop, const std::vector<Point2>& pts) {
  double a = 0;
  for (size_t k = 0; k < loop.size(); ++k) {
    const Point2 &p = pts[size_t(loop[k])], &q = pts[size_t(loop[(k + 1) % loop.size()])];
    a += p.x * q.y - p.y * q.x;
  }
  return a;
}

std::vector<std::array<int32_t, 3>> triangulate_loops(const std::vector<std::vector<int32_t>>& loops,
                                                      const std::vector<Point2>& points) {
  // Outer loops and holes by orientation; each hole goes into the smallest outer loop around it,
  // rightmost holes first so that later bridges see the earlier ones as part of the boundary.
  std::vector<std::vector<int32_t>> outer;
  std::vector<double> outer_area;
  std::vector<std::pair<double, size_t>> holes;
  for (size_t k = 0; k < loops.size(); ++k) {
    if (loops[k].size() < 3) continue;
    const double a = twice_area(loops[k], points);
    if (a > 0) {
      outer.push_back(loops[k]);
      outer_area.push_back(a);
    } else {
      double right = -std::numeric_limits<double>::infinity();
      for (int32_t v : loops[k]) right = std::max(right, points[size_t(v)].x);
      holes.emplace_back(-right, k);
    }
  }
  std::sort(holes.begin(), holes.end());
  for (const auto& [neg_right, k] : holes) {
    const std::vector<int32_t>& h = loops[k];
    size_t host = outer.size();
    for (size_t o = 0; o < outer.size(); ++o)
      if (inside_loop(points[size_t(h[0])], outer[o], points) &&
          (host == outer.size() || outer_area[o] < outer_area[host]))
        host = o;
    if (host == outer.size()) continue;  // a hole in nothing: no area to fill
    bridge(outer[host], h, loops, points);
  }
  std::vector<std::array<int32_t, 3>> out;
  for (auto& loop : outer) clip_ears(loop, points, out);
  return out;
}

}  // namespace pd
