#include "host/fragments/voronoi_complex.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <parallel/algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/fragments/loop_triangulation.h"
#include "host/geometry/convex_cell.h"
#include "host/geometry/inside_test.h"
#include "host/geometry/tri_mesh.h"

namespace pd {

namespace {

// The point where three planes n_k . y = h_k meet (Cramer's rule).
Vec3d meet(const Vec3d& n1, double h1, const Vec3d& n2, double h2, const Vec3d& n3, double h3) {
  const Vec3d c23 = cross(n2, n3), c31 = cross(n3, n1), c12 = cross(n1, n2);
  const double det = dot(n1, c23);
  return (1 / det) * (h1 * c23 + h2 * c31 + h3 * c12);
}

bool less_xyz(const Vec3d& a, const Vec3d& b) {
  return a[0] != b[0] ? a[0] < b[0] : a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
}

// A face plane of cell i in canonical form: for a bisector, n = s_b - s_a through the midpoint of
// the sites a < b, the same numbers in both cells; `sign` turns it so that the cell is where
// sign * n . (x - at) <= 0. A box side (id < 0) is the cell's own.
struct Plane {
  Vec3d n, at;
  double sign;
  double side(const Vec3d& x) const { return sign * dot(n, x - at); }
};

// One point of a cell, by what defines it: a cell corner (a = corner index), a surface vertex
// (a), a crossing of triangle edge a-b (a < b) with the face of neighbour c, or a crossing of
// triangle a with the cell edge between the faces of neighbours b < c.
struct Key {
  enum Kind : int32_t { kCorner, kVertex, kEdgePlane, kTriangleEdge } kind;
  int32_t a, b, c;
  bool operator==(const Key& o) const { return kind == o.kind && a == o.a && b == o.b && c == o.c; }
};

// A cell's output: its points and its polygons over them, each bordering a site (>= 0) or the
// surface (-1).
struct CellOut {
  std::vector<Vec3d> point;
  std::vector<int32_t> poly_start{0}, poly_point, poly_other;
  int32_t failed_faces = 0;

  void add_polygon(const int32_t* p, size_t n, int32_t other) {
    poly_point.insert(poly_point.end(), p, p + n);
    poly_start.push_back(int32_t(poly_point.size()));
    poly_other.push_back(other);
  }
};

class CellBuilder {
 public:
  CellBuilder(const ParticleGeometry& g, const InsideTest& inside)
      : g_(g), cells_(g.cells), inside_(inside) {}

  void build(int32_t i, CellOut& out) {
    i_ = i;
    out_ = &out;
    out = CellOut();
    keys_.clear();
    rebuild_cell();
    const auto& faces = cell_.faces();
    if (faces.empty()) return;
    corner_points();
    const int64_t t0 = cells_.triangle_offset[size_t(i)], t1 = cells_.triangle_offset[size_t(i) + 1];
    tris_.assign(cells_.triangles.begin() + t0, cells_.triangles.begin() + t1);
    if (tris_.empty()) {
      // All inside: the cell's faces as they are.
      for (const auto& f : faces) {
        poly_.clear();
        for (int32_t c : f.corners) poly_.push_back(corner_point(c));
        out.add_polygon(poly_.data(), poly_.size(), f.id >= 0 ? f.id : -1);
      }
      return;
    }
    planes_.clear();
    for (const auto& f : faces) planes_.push_back(plane(f.id));
    edge_faces();
    for (size_t k = 0; k < faces.size(); ++k) face_inside(k);
    for (int32_t t : tris_) surface_patch(t);
  }

 private:
  // The cell: the cube around the site cut by the bisector planes of its neighbours, in the order
  // the geometry stage found them.
  void rebuild_cell() {
    const Vec3d& s = site(i_);
    const double rho = cells_.cube_half_side;
    cell_.reset(s - Vec3d{rho, rho, rho}, s + Vec3d{rho, rho, rho});
    for (int64_t k = cells_.face_offset[size_t(i_)]; k < cells_.face_offset[size_t(i_) + 1]; ++k) {
      const int32_t j = cells_.face_site[size_t(k)];
      if (j < 0) continue;
      const Vec3d& sj = site(j);
      cell_.clip(sj - s, 0.5 * (dot(sj, sj) - dot(s, s)), j);
    }
  }

  const Vec3d& site(int32_t j) const { return g_.position[size_t(j)]; }

  Plane plane(int32_t id) const {
    if (id >= 0) {
      const int32_t a = std::min(i_, id), b = std::max(i_, id);
      return {site(b) - site(a), 0.5 * (site(a) + site(b)), i_ == a ? 1.0 : -1.0};
    }
    const int s = -1 - id, axis = s / 2;
    const bool high = s % 2 == 1;
    Vec3d n{0, 0, 0}, at = site(i_);
    n[size_t(axis)] = 1;
    at[size_t(axis)] += high ? cells_.cube_half_side : -cells_.cube_half_side;
    return {n, at, high ? 1.0 : -1.0};
  }

  // The faces at each corner; a corner on three bisector faces is the Voronoi vertex of four sites,
  // computed from the sites in increasing order, relative to the first.
  void corner_points() {
    int32_t most = 0;
    for (const auto& f : cell_.faces())
      for (int32_t c : f.corners) most = std::max(most, c + 1);
    corner_faces_.assign(size_t(most), {0, -1, -1, -1});
    corner_point_.assign(size_t(most), -1);
    for (const auto& f : cell_.faces())
      for (int32_t c : f.corners) {
        auto& cf = corner_faces_[size_t(c)];
        if (cf[0] < 3) cf[size_t(1 + cf[0])] = f.id;
        ++cf[0];
      }
  }

  Vec3d corner_position(int32_t c) const {
    const auto& cf = corner_faces_[size_t(c)];
    if (cf[0] != 3 || cf[1] < 0 || cf[2] < 0 || cf[3] < 0) return cell_.corner(c);
    std::array<int32_t, 4> s{i_, cf[1], cf[2], cf[3]};
    std::sort(s.begin(), s.end());
    const Vec3d& o = site(s[0]);
    const Vec3d n1 = site(s[1]) - o, n2 = site(s[2]) - o, n3 = site(s[3]) - o;
    return o + meet(n1, 0.5 * dot(n1, n1), n2, 0.5 * dot(n2, n2), n3, 0.5 * dot(n3, n3));
  }

  int32_t corner_point(int32_t c) {
    int32_t& p = corner_point_[size_t(c)];
    if (p < 0) {
      p = int32_t(out_->point.size());
      out_->point.push_back(corner_position(c));
      keys_.push_back({Key::kCorner, c, 0, 0});
    }
    return p;
  }

  // The point of `key`, added at `x()` when new.
  template <class Position>
  int32_t point(const Key& key, Position x) {
    for (size_t k = 0; k < keys_.size(); ++k)
      if (keys_[k] == key) return int32_t(k);
    keys_.push_back(key);
    out_->point.push_back(x());
    return int32_t(out_->point.size() - 1);
  }

  int32_t vertex_point(int32_t v) {
    return point({Key::kVertex, v, 0, 0}, [&] { return cells_.surface.vertices[size_t(v)]; });
  }

  // Triangle edge va-vb crosses the face of neighbour id.
  int32_t edge_plane_point(int32_t va, int32_t vb, int32_t id) {
    if (va > vb) std::swap(va, vb);
    return point({Key::kEdgePlane, va, vb, id}, [&] {
      const Plane p = plane(id);
      const Vec3d &a = cells_.surface.vertices[size_t(va)], &b = cells_.surface.vertices[size_t(vb)];
      const double fa = dot(p.n, a - p.at), fb = dot(p.n, b - p.at);
      return a + (fa / (fa - fb)) * (b - a);
    });
  }

  // Triangle t crosses the cell edge between the faces of neighbours p and q.
  int32_t triangle_edge_point(int32_t t, int32_t p, int32_t q) {
    if (p > q) std::swap(p, q);
    return point({Key::kTriangleEdge, t, p, q}, [&] {
      const Triangle& tri = cells_.surface.triangles[size_t(t)];
      const Vec3d& v0 = cells_.surface.vertices[size_t(tri[0])];
      const Vec3d nt =
          cross(cells_.surface.vertices[size_t(tri[1])] - v0, cells_.surface.vertices[size_t(tri[2])] - v0);
      if (p >= 0) {
        std::array<int32_t, 3> s{i_, p, q};
        std::sort(s.begin(), s.end());
        const Vec3d& o = site(s[0]);
        const Vec3d n1 = site(s[1]) - o, n2 = site(s[2]) - o;
        return o + meet(n1, 0.5 * dot(n1, n1), n2, 0.5 * dot(n2, n2), nt, dot(nt, v0 - o));
      }
      const Vec3d& o = site(i_);
      const Plane a = plane(p), b = plane(q);
      return o + meet(a.n, dot(a.n, a.at - o), b.n, dot(b.n, b.at - o), nt, dot(nt, v0 - o));
    });
  }

  // For each face and corner: the face across the edge from that corner to the next one.
  void edge_faces() {
    const auto& faces = cell_.faces();
    edge_list_.clear();
    for (size_t k = 0; k < faces.size(); ++k) {
      const auto& c = faces[k].corners;
      for (size_t j = 0; j < c.size(); ++j) edge_list_.push_back({c[j], c[(j + 1) % c.size()], int32_t(k)});
    }
    std::sort(edge_list_.begin(), edge_list_.end());
    across_.assign(faces.size(), {});
    for (size_t k = 0; k < faces.size(); ++k) {
      const auto& c = faces[k].corners;
      across_[k].assign(c.size(), -1);
      for (size_t j = 0; j < c.size(); ++j) {
        const std::array<int32_t, 3> want{c[(j + 1) % c.size()], c[j], -1};
        const auto it = std::lower_bound(edge_list_.begin(), edge_list_.end(), want);
        if (it != edge_list_.end() && (*it)[0] == want[0] && (*it)[1] == want[1]) across_[k][j] = (*it)[2];
      }
    }
  }

  // The points along cell edge a-b (a, b corner indices) in order from a: a, its crossings with
  // the surface triangles (each the point of triangle t and the faces of ids p and q), b.
  const std::vector<int32_t>& edge_points(int32_t a, int32_t b, int32_t p, int32_t q) {
    // Crossing parameters from the lexicographically smaller end, so every cell orders them alike.
    const Vec3d xa = out_->point[size_t(corner_point(a))], xb = out_->point[size_t(corner_point(b))];
    const bool flip = less_xyz(xb, xa);
    hits_.clear();
    const auto& v = cells_.surface.vertices;
    for (int32_t t : tris_) {
      const Triangle& tri = cells_.surface.triangles[size_t(t)];
      const double s = flip ? segment_hits(xb, xa, v[size_t(tri[0])], v[size_t(tri[1])], v[size_t(tri[2])])
                            : segment_hits(xa, xb, v[size_t(tri[0])], v[size_t(tri[1])], v[size_t(tri[2])]);
      if (s > 0) hits_.emplace_back(flip ? 1 - s : s, t);
    }
    std::sort(hits_.begin(), hits_.end());
    edge_points_.assign(1, corner_point(a));
    for (const auto& [s, t] : hits_) edge_points_.push_back(triangle_edge_point(t, p, q));
    edge_points_.push_back(corner_point(b));
    return edge_points_;
  }

  // The part of face k inside the object: the inside pieces of its edges and the segments where
  // surface triangles cross it, linked into loops and triangulated (or the face itself when it is
  // all inside).
  void face_inside(size_t k) {
    const auto& f = cell_.faces()[k];
    const Plane& pf = planes_[k];
    const int32_t other = f.id >= 0 ? f.id : -1;
    from_.clear();
    to_.clear();
    bool whole = true;
    // Edge pieces, counter-clockwise, where their midpoint is inside.
    const size_t m = f.corners.size();
    for (size_t j = 0; j < m; ++j) {
      const int32_t g = across_[k][j];
      if (g < 0) {
        ++out_->failed_faces;
        return;
      }
      const std::vector<int32_t>& pts =
          edge_points(f.corners[j], f.corners[(j + 1) % m], f.id, cell_.faces()[size_t(g)].id);
      for (size_t q = 0; q + 1 < pts.size(); ++q) {
        const Vec3d mid = 0.5 * (out_->point[size_t(pts[q])] + out_->point[size_t(pts[q + 1])]);
        if (!inside_.inside(mid)) {
          whole = false;
          continue;
        }
        from_.push_back(pts[q]);
        to_.push_back(pts[q + 1]);
      }
      whole = whole && pts.size() == 2;
    }
    // Segments of the surface triangles in the face's plane, clipped to the cell, running with the
    // object's inside on their left (seen from outside the cell).
    const Vec3d out_normal = pf.sign * pf.n;
    const auto& v = cells_.surface.vertices;
    for (int32_t t : tris_) {
      const Triangle& tri = cells_.surface.triangles[size_t(t)];
      double side[3];
      for (int c = 0; c < 3; ++c) side[c] = dot(pf.n, v[size_t(tri[c])] - pf.at);
      int32_t ends[2];
      int found = 0;
      for (int c = 0; c < 3 && found < 2; ++c) {
        const int d = (c + 1) % 3;
        if ((side[c] > 0) != (side[d] > 0)) ends[found++] = edge_plane_point(tri[c], tri[d], f.id);
      }
      if (found < 2) continue;
      Vec3d e0 = out_->point[size_t(ends[0])], e1 = out_->point[size_t(ends[1])];
      const Vec3d nt = cross(v[size_t(tri[1])] - v[size_t(tri[0])], v[size_t(tri[2])] - v[size_t(tri[0])]);
      if (dot(e1 - e0, cross(out_normal, nt)) < 0) {
        std::swap(ends[0], ends[1]);
        std::swap(e0, e1);
      }
      // Clip to the other faces; an end cut by face g is the triangle's crossing with that edge.
      double s0 = 0, s1 = 1;
      int32_t g0 = -1, g1 = -1;
      bool empty = false;
      for (size_t g = 0; g < planes_.size() && !empty; ++g) {
        if (g == k) continue;
        const double a = planes_[g].side(e0), b = planes_[g].side(e1);
        if (a > 0 && b > 0) empty = true;
        if (a > 0 && b <= 0 && a / (a - b) > s0) s0 = a / (a - b), g0 = int32_t(g);
        if (b > 0 && a <= 0 && a / (a - b) < s1) s1 = a / (a - b), g1 = int32_t(g);
      }
      if (empty || s0 >= s1) continue;
      const int32_t start = g0 < 0 ? ends[0] : triangle_edge_point(t, f.id, cell_.faces()[size_t(g0)].id);
      const int32_t end = g1 < 0 ? ends[1] : triangle_edge_point(t, f.id, cell_.faces()[size_t(g1)].id);
      from_.push_back(start);
      to_.push_back(end);
      whole = false;
    }
    if (from_.empty()) return;
    if (whole) {
      poly_.clear();
      for (int32_t c : f.corners) poly_.push_back(corner_point(c));
      out_->add_polygon(poly_.data(), poly_.size(), other);
      return;
    }
    // Loops: each point has one edge out and one in.
    loops_.clear();
    used_.assign(from_.size(), 0);
    for (size_t e = 0; e < from_.size(); ++e) {
      if (used_[e]) continue;
      std::vector<int32_t> loop;
      size_t at = e;
      while (!used_[at]) {
        used_[at] = 1;
        loop.push_back(from_[at]);
        size_t next = from_.size(), count = 0;
        for (size_t x = 0; x < from_.size(); ++x)
          if (from_[x] == to_[at]) next = x, ++count;
        if (count != 1) {
          ++out_->failed_faces;
          return;
        }
        at = next;
      }
      if (at != e) {
        ++out_->failed_faces;
        return;
      }
      loops_.push_back(std::move(loop));
    }
    // Triangles in the face's plane (u, w, outward normal right-handed).
    const Vec3d normal = (1 / norm(out_normal)) * out_normal;
    const Vec3d u = cross(std::abs(normal[0]) < 0.6 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0}, normal);
    const Vec3d w = cross(normal, u);
    flat_.resize(out_->point.size());
    for (const auto& loop : loops_)
      for (int32_t p : loop)
        flat_[size_t(p)] = {dot(out_->point[size_t(p)], u), dot(out_->point[size_t(p)], w)};
    for (const auto& tri : triangulate_loops(loops_, flat_)) out_->add_polygon(tri.data(), 3, other);
  }

  // The part of surface triangle t inside the cell: the triangle clipped by every face, each new
  // point named by the edge it lies on (a triangle edge or a cut along another face).
  void surface_patch(int32_t t) {
    const Triangle& tri = cells_.surface.triangles[size_t(t)];
    // Polygon points, each with the edge to the next: a triangle edge (label >= 0: the index of its
    // first vertex in the triangle) or the cut along face g (label -1 - g).
    poly_.clear();
    label_.clear();
    for (int c = 0; c < 3; ++c) {
      poly_.push_back(vertex_point(tri[size_t(c)]));
      label_.push_back(c);
    }
    const auto& faces = cell_.faces();
    for (size_t g = 0; g < faces.size() && poly_.size() >= 3; ++g) {
      next_poly_.clear();
      next_label_.clear();
      const size_t n = poly_.size();
      for (size_t k = 0; k < n; ++k) {
        const int32_t a = poly_[k], b = poly_[(k + 1) % n], l = label_[k];
        const bool a_in = planes_[g].side(out_->point[size_t(a)]) <= 0,
                   b_in = planes_[g].side(out_->point[size_t(b)]) <= 0;
        if (a_in) {
          next_poly_.push_back(a);
          next_label_.push_back(l);
        }
        if (a_in == b_in) continue;
        const int32_t x = l >= 0 ? edge_plane_point(tri[size_t(l)], tri[size_t((l + 1) % 3)], faces[g].id)
                                 : triangle_edge_point(t, faces[size_t(-1 - l)].id, faces[g].id);
        next_poly_.push_back(x);
        next_label_.push_back(a_in ? -1 - int32_t(g) : l);
      }
      poly_.swap(next_poly_);
      label_.swap(next_label_);
    }
    if (poly_.size() >= 3) out_->add_polygon(poly_.data(), poly_.size(), -1);
  }

  const ParticleGeometry& g_;
  const VoronoiCells& cells_;
  const InsideTest& inside_;
  int32_t i_ = 0;
  CellOut* out_ = nullptr;
  ConvexCell cell_{Vec3d{0, 0, 0}, Vec3d{1, 1, 1}};
  std::vector<Key> keys_;
  std::vector<std::array<int32_t, 4>> corner_faces_;  // count, then up to 3 face ids
  std::vector<int32_t> corner_point_;
  std::vector<int32_t> tris_;
  std::vector<Plane> planes_;
  std::vector<std::array<int32_t, 3>> edge_list_;
  std::vector<std::vector<int32_t>> across_;
  std::vector<int32_t> edge_points_;
  std::vector<std::pair<double, int32_t>> hits_;
  std::vector<int32_t> from_, to_, poly_, label_, next_poly_, next_label_;
  std::vector<uint8_t> used_;
  std::vector<std::vector<int32_t>> loops_;
  std::vector<Point2> flat_;
};

// Hash of a position's bits, for joining equal points of different cells.
uint64_t position_hash(const Vec3d& x) {
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (double c : x) {
    uint64_t b;
    std::memcpy(&b, &c, sizeof b);
    h ^= b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
  }
  return h;
}

}  // namespace

ElementComplex voronoi_complex(const ParticleGeometry& g, int32_t first_particle,
                               VoronoiComplexReport* report) {
  const VoronoiCells& cells = g.cells;
  const size_t n = g.size();
  if (g.kind != ElementKind::voronoi || cells.face_offset.size() != n + 1 ||
      cells.triangle_offset.size() != n + 1)
    throw std::invalid_argument("voronoi_complex needs Voronoi cells, one per particle (got " +
                                std::to_string(cells.face_offset.size()) + " cell offsets for " +
                                std::to_string(n) + " particles)");

  // Each cell's points and polygons, in parallel.
  const InsideTest inside(cells.surface);
  std::vector<CellOut> out(n);
#pragma omp parallel
  {
    CellBuilder builder(g, inside);
#pragma omp for schedule(dynamic, 256)
    for (int64_t i = 0; i < int64_t(n); ++i) builder.build(int32_t(i), out[size_t(i)]);
  }

  // Points of all cells joined by exact position: sort by a hash of the bits, then equal runs.
  struct Entry {
    uint64_t hash;
    int32_t cell, k;
    bool operator<(const Entry& o) const {
      return hash != o.hash ? hash < o.hash : cell != o.cell ? cell < o.cell : k < o.k;
    }
  };
  std::vector<int64_t> point_start(n + 1, 0);
  for (size_t i = 0; i < n; ++i) point_start[i + 1] = point_start[i] + int64_t(out[i].point.size());
  std::vector<Entry> order(static_cast<size_t>(point_start[n]));
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < int64_t(n); ++i)
    for (size_t k = 0; k < out[size_t(i)].point.size(); ++k)
      order[size_t(point_start[size_t(i)]) + k] = {position_hash(out[size_t(i)].point[k]), int32_t(i),
                                                   int32_t(k)};
  __gnu_parallel::sort(order.begin(), order.end());
  auto position_of = [&](const Entry& e) { return out[size_t(e.cell)].point[size_t(e.k)]; };
  auto flat = [&](const Entry& e) { return size_t(point_start[size_t(e.cell)] + e.k); };
  std::vector<int32_t> same(order.size());  // per point: the first point of its class in cell order
  for (size_t at = 0; at < order.size();) {
    size_t end = at + 1;
    while (end < order.size() && order[end].hash == order[at].hash) ++end;
    // Within a run of equal hashes (in cell order), equal positions are one vertex.
    for (size_t k = at; k < end; ++k) {
      const Vec3d x = position_of(order[k]);
      size_t j = at;
      while (j < k && !(position_of(order[j]) == x)) ++j;
      same[flat(order[k])] = int32_t(flat(order[j]));
    }
    at = end;
  }
  order = std::vector<Entry>();

  // Elements: each cell's distinct vertices as corners, its polygons as faces.
  // Vertices numbered in order of first use.
  ElementComplex c;
  std::vector<int32_t> vertex(same.size(), -1);
  auto vertex_of = [&](size_t i, int32_t k) {
    const size_t first = size_t(same[size_t(point_start[i] + k)]);
    if (vertex[first] < 0) {
      vertex[first] = int32_t(c.vertices.size());
      c.vertices.push_back(out[i].point[size_t(k)]);
    }
    return vertex[first];
  };
  size_t failed = 0, boundary = 0;
  std::vector<int32_t> corner_of, face;
  for (size_t i = 0; i < n; ++i) {
    const CellOut& o = out[i];
    failed += size_t(o.failed_faces);
    boundary += cells.triangle_offset[i + 1] > cells.triangle_offset[i];
    c.begin_element(first_particle + int32_t(i));
    const int32_t first = int32_t(c.corner_vertex.size());
    for (size_t q = 0; q + 1 < o.poly_start.size(); ++q) {
      face.clear();
      for (int32_t k = o.poly_start[q]; k < o.poly_start[q + 1]; ++k) {
        const int32_t v = vertex_of(i, o.poly_point[size_t(k)]);
        if (corner_of.size() <= size_t(v))
          corner_of.resize(c.vertices.size() + c.vertices.size() / 2 + 64, -1);
        if (corner_of[size_t(v)] < 0) corner_of[size_t(v)] = c.add_corner(v);
        if (face.empty() || face.back() != corner_of[size_t(v)]) face.push_back(corner_of[size_t(v)]);
      }
      while (face.size() > 1 && face.back() == face.front()) face.pop_back();
      const int32_t other = o.poly_other[q];
      if (face.size() >= 3) c.add_face(face.data(), face.size(), other >= 0 ? first_particle + other : -1);
    }
    for (int64_t k = first; k < int64_t(c.corner_vertex.size()); ++k)
      corner_of[size_t(c.corner_vertex[size_t(k)])] = -1;
  }
  if (report) *report = {boundary, failed};
  return c;
}

}  // namespace pd
