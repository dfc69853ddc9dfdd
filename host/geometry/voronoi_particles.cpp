#include "host/geometry/voronoi_particles.h"

#include <algorithm>
#include <cmath>

#include "host/geometry/convex_cell.h"
#include "host/geometry/curve_order.h"
#include "host/geometry/grid_particles.h"
#include "host/geometry/inside_test.h"
#include "host/geometry/poisson_disk.h"
#include "host/geometry/tri_mesh.h"

namespace pd {

namespace {

// Uniform 3D bins of items (sites or triangles) by bounding box.
class Bins {
 public:
  Bins(const Box3d& box, double cell) : lo_(box.lo), inv_(1 / cell) {
    for (int a = 0; a < 3; ++a) n_[a] = std::max(1, std::min(1024, int(std::ceil(box.size()[a] * inv_)) + 1));
    start_.assign(size_t(n_[0]) * n_[1] * n_[2] + 1, 0);
  }
  // Two passes over the items: count(lo, hi) for each, then finish_count(), then fill(...).
  void range(const Vec3d& lo, const Vec3d& hi, int a0[3], int a1[3]) const {
    for (int a = 0; a < 3; ++a) {
      a0[a] = std::clamp(int(std::floor((lo[a] - lo_[a]) * inv_)), 0, n_[a] - 1);
      a1[a] = std::clamp(int(std::floor((hi[a] - lo_[a]) * inv_)), 0, n_[a] - 1);
    }
  }
  template <class Visit>
  void for_bins(const Vec3d& lo, const Vec3d& hi, Visit visit) const {
    int a0[3], a1[3];
    range(lo, hi, a0, a1);
    for (int z = a0[2]; z <= a1[2]; ++z)
      for (int y = a0[1]; y <= a1[1]; ++y)
        for (int x = a0[0]; x <= a1[0]; ++x) visit((size_t(z) * n_[1] + y) * n_[0] + x);
  }
  void build(size_t count, const std::vector<Box3d>& boxes) {
    for (size_t i = 0; i < count; ++i) for_bins(boxes[i].lo, boxes[i].hi, [&](size_t b) { ++start_[b + 1]; });
    for (size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    items_.resize(size_t(start_.back()));
    std::vector<int64_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < count; ++i)
      for_bins(boxes[i].lo, boxes[i].hi, [&](size_t b) { items_[size_t(fill[b]++)] = int32_t(i); });
  }
  template <class Visit>
  void for_items(const Vec3d& lo, const Vec3d& hi, Visit visit) const {
    for_bins(lo, hi, [&](size_t b) {
      for (int64_t k = start_[b]; k < start_[b + 1]; ++k) visit(items_[size_t(k)]);
    });
  }
  // Points binned (one bin each): a copy of their positions in bin order, so a search reads
  // contiguous memory; then for_points visits (item, position).
  void keep_points(const std::vector<Vec3d>& points) {
    point_.resize(items_.size());
    for (size_t k = 0; k < items_.size(); ++k) point_[k] = points[size_t(items_[k])];
  }
  template <class Visit>
  void for_points(const Vec3d& lo, const Vec3d& hi, Visit visit) const {
    for_bins(lo, hi, [&](size_t b) {
      for (int64_t k = start_[b]; k < start_[b + 1]; ++k) visit(items_[size_t(k)], point_[size_t(k)]);
    });
  }
  const std::vector<int32_t>& items() const { return items_; }

 private:
  Vec3d lo_;
  double inv_;
  int n_[3];
  std::vector<int64_t> start_;
  std::vector<int32_t> items_;
  std::vector<Vec3d> point_;
};

double polygon_area(const std::vector<Vec3d>& poly) {
  Vec3d sum{0, 0, 0};
  for (size_t k = 1; k + 1 < poly.size(); ++k) sum = sum + cross(poly[k] - poly[0], poly[k + 1] - poly[0]);
  return 0.5 * norm(sum);
}

// One cell's results.
struct CellResult {
  double volume = 0;
  std::vector<int32_t> faces, triangles, adjacent;
};

// Volume of cell ∩ solid, its trimtope triangles and its neighbours across faces inside the solid.
class CellClipper {
 public:
  CellClipper(const TriMesh& solid, const InsideTest& inside, const Bins& triangle_bins)
      : solid_(solid), inside_(inside), bins_(triangle_bins), stamp_(solid.triangles.size(), -1) {}

  void measure(int32_t site_id, const Vec3d& site, const ConvexCell& cell, CellResult& out) {
    out.faces.clear();
    out.triangles.clear();
    out.adjacent.clear();
    for (const auto& f : cell.faces()) out.faces.push_back(f.id);

    // Surface pieces: each candidate triangle clipped to the cell; (1/3) h_T area for each.
    Vec3d lo, hi;
    cell.bounds(lo, hi);
    double part = 0;
    bins_.for_items(lo, hi, [&](int32_t t) {
      if (stamp_[size_t(t)] == site_id) return;
      stamp_[size_t(t)] = site_id;
      const Triangle& tri = solid_.triangles[size_t(t)];
      poly_ = {solid_.vertices[tri[0]], solid_.vertices[tri[1]], solid_.vertices[tri[2]]};
      for (const auto& f : cell.faces()) {
        clip_polygon(poly_, f.normal, f.offset, scratch_);
        if (poly_.size() < 3) return;
      }
      const double area = polygon_area(poly_);
      if (!(area > 0)) return;
      const Vec3d tn = cross(solid_.vertices[tri[1]] - solid_.vertices[tri[0]],
                             solid_.vertices[tri[2]] - solid_.vertices[tri[0]]);
      part += dot((1 / norm(tn)) * tn, solid_.vertices[tri[0]] - site) * area;
      out.triangles.push_back(t);
    });
    if (out.triangles.empty()) {
      // The surface does not cross the cell: all of it is inside (its site is).
      out.volume = cell.volume(site);
      for (const auto& f : cell.faces())
        if (f.id >= 0) out.adjacent.push_back(f.id);
      return;
    }
    std::sort(out.triangles.begin(), out.triangles.end());

    // Faces: (1/3) h_F area(F ∩ solid), the area by Green's theorem in the face's plane.
    edge_cache_.clear();
    for (const auto& f : cell.faces()) {
      const double h = f.offset - dot(f.normal, site);
      const Vec3d q = site + h * f.normal;  // the site's projection on the face's plane
      double twice_area = 0;
      // Surface segments in the face: each crossing triangle cut by the plane, then by the cell.
      for (int32_t t : out.triangles) twice_area += surface_segment(cell, f, t, q);
      // The face's edges, where inside the solid.
      const size_t m = f.corners.size();
      for (size_t k = 0; k < m; ++k) {
        const int32_t ia = f.corners[k], ib = f.corners[(k + 1) % m];
        const Vec3d& a = cell.corner(ia);
        const Vec3d& b = cell.corner(ib);
        const Vec3d edge_normal = cross(b - a, f.normal);
        const double len = norm(edge_normal);
        if (!(len > 0)) continue;
        twice_area += dot((1 / len) * edge_normal, a - q) * inside_length(ia, ib, a, b, out.triangles);
      }
      const double area = 0.5 * twice_area;
      part += h * area;
      if (f.id >= 0 && area > 1e-12 * h * h) out.adjacent.push_back(f.id);
    }
    out.volume = part / 3;
  }

 private:
  // (m . (x - q)) * length of triangle t ∩ plane of f ∩ cell, m the outward normal in the plane.
  double surface_segment(const ConvexCell& cell, const ConvexCell::Face& f, int32_t t, const Vec3d& q) {
    const Triangle& tri = solid_.triangles[size_t(t)];
    Vec3d p[3];
    double s[3];
    for (int c = 0; c < 3; ++c) {
      p[c] = solid_.vertices[tri[c]];
      s[c] = dot(f.normal, p[c]) - f.offset;
    }
    Vec3d ends[2];
    int found = 0;
    for (int c = 0; c < 3 && found < 2; ++c) {
      const int d = (c + 1) % 3;
      if ((s[c] < 0) != (s[d] < 0)) ends[found++] = p[c] + (s[c] / (s[c] - s[d])) * (p[d] - p[c]);
    }
    if (found < 2) return 0;
    // Clip the segment by the cell's other planes.
    double t0 = 0, t1 = 1;
    const Vec3d dir = ends[1] - ends[0];
    for (const auto& g : cell.faces()) {
      if (&g == &f) continue;
      const double s0 = dot(g.normal, ends[0]) - g.offset, ds = dot(g.normal, dir);
      if (ds == 0) {
        if (s0 > 0) return 0;
        continue;
      }
      const double tc = -s0 / ds;
      if (ds > 0)
        t1 = std::min(t1, tc);
      else
        t0 = std::max(t0, tc);
      if (t0 >= t1) return 0;
    }
    const Vec3d tn = cross(p[1] - p[0], p[2] - p[0]);
    Vec3d m = tn - dot(tn, f.normal) * f.normal;
    const double ml = norm(m);
    if (!(ml > 0)) return 0;
    m = (1 / ml) * m;
    return dot(m, ends[0] - q) * (t1 - t0) * norm(dir);
  }

  // Length of the cell edge a-b inside the solid: the intervals between its crossings with the
  // surface, each classified by the inside test at its midpoint. Cached per edge.
  double inside_length(int32_t ia, int32_t ib, const Vec3d& a, const Vec3d& b,
                       const std::vector<int32_t>& tris) {
    const uint64_t key = (uint64_t(uint32_t(std::min(ia, ib))) << 32) | uint32_t(std::max(ia, ib));
    for (const auto& [k, v] : edge_cache_)
      if (k == key) return v;
    ts_.assign(1, 0.0);
    for (int32_t t : tris) {
      const Triangle& tri = solid_.triangles[size_t(t)];
      const double hit =
          segment_hits(a, b, solid_.vertices[tri[0]], solid_.vertices[tri[1]], solid_.vertices[tri[2]]);
      if (hit > 0) ts_.push_back(hit);
    }
    ts_.push_back(1.0);
    std::sort(ts_.begin(), ts_.end());
    double inside = 0;
    for (size_t k = 0; k + 1 < ts_.size(); ++k) {
      if (!(ts_[k + 1] > ts_[k])) continue;
      if (inside_.inside(a + (0.5 * (ts_[k] + ts_[k + 1])) * (b - a))) inside += ts_[k + 1] - ts_[k];
    }
    const double length = inside * norm(b - a);
    edge_cache_.emplace_back(key, length);
    return length;
  }

  const TriMesh& solid_;
  const InsideTest& inside_;
  const Bins& bins_;
  std::vector<int32_t> stamp_;  // last site that looked at each triangle
  std::vector<Vec3d> poly_, scratch_;
  std::vector<double> ts_;
  std::vector<std::pair<uint64_t, double>> edge_cache_;
};

// Typical number density of maximal Poisson-disk samples in 3D, per r^3 (for the budget check).
constexpr double kPoissonDensity = 0.7;

}  // namespace

ParticleGeometry voronoi_particles(const TriMesh& solid, double r, uint64_t seed, int64_t max_particles,
                                   const std::string& name) {
  check_particle_budget(signed_volume(solid), r * r * r / kPoissonDensity, max_particles, name,
                        "minimum distance " + std::to_string(r) + " m");
  ParticleGeometry g;
  StageClock clock(&g.stages);
  const InsideTest inside(solid);
  g.kind = ElementKind::voronoi;
  clock.lap("inside test");
  g.position = poisson_disk_points(solid, inside, r, seed);
  g.position = permuted(g.position, morton_order(g.position));  // particles in curve order
  clock.lap("Poisson-disk sites");
  const size_t n = g.size();
  const double rho = 2 * r;  // cells are cut to the cube of half-side rho around their site

  // Sites binned by position twice (cells of 2.5 r and of 2 rho = 4 r, so candidates within
  // either distance are in the 27 bins around),
  // triangles by their bounding boxes.
  Box3d site_box;
  for (const Vec3d& p : g.position) site_box.add(p);
  std::vector<Box3d> boxes(n);
  for (size_t i = 0; i < n; ++i) boxes[i].add(g.position[i]);
  Bins sites(site_box, 2 * rho);
  sites.build(n, boxes);
  sites.keep_points(g.position);
  Bins near_sites(site_box, 2.5 * r);
  near_sites.build(n, boxes);
  near_sites.keep_points(g.position);
  // Cells are made in bin order (neighbours at once, for the caches); each into its own slot.
  const std::vector<int32_t>& order = near_sites.items();
  std::vector<Box3d> tri_boxes(solid.triangles.size());
  for (size_t t = 0; t < solid.triangles.size(); ++t)
    for (int32_t v : solid.triangles[t]) tri_boxes[t].add(solid.vertices[v]);
  Bins triangle_bins(bounds(solid), rho);
  triangle_bins.build(tri_boxes.size(), tri_boxes);

  clock.lap("binning");
  std::vector<CellResult> results(n);
#pragma omp parallel
  {
    CellClipper clipper(solid, inside, triangle_bins);
    std::vector<std::pair<double, int32_t>> near;
    ConvexCell cell(Vec3d{0, 0, 0}, Vec3d{1, 1, 1});
#pragma omp for schedule(dynamic, 256)
    for (int64_t k = 0; k < int64_t(n); ++k) {
      const int32_t i = order[size_t(k)];
      const Vec3d& s = g.position[size_t(i)];
      // Candidate neighbours, nearest first: those within 2.5 r, which close most cells, then
      // (when the cell still reaches beyond 1.25 r) the rest within 2 rho = 4 r.
      cell.reset(s - Vec3d{rho, rho, rho}, s + Vec3d{rho, rho, rho});
      double reach2 = 3 * rho * rho;  // (max corner distance)^2
      double done2 = 0;               // candidates up to this squared distance were used
      for (const double radius : {2.5 * r, 2 * rho}) {
        if (4 * reach2 <= done2) break;
        near.clear();
        const Vec3d reach{radius, radius, radius};
        (radius < 2 * rho ? near_sites : sites)
            .for_points(s - reach, s + reach, [&](int32_t j, const Vec3d& q) {
              const double d2 = distance2(s, q);
              if (j != i && d2 <= radius * radius && d2 > done2) near.emplace_back(d2, j);
            });
        std::sort(near.begin(), near.end());
        for (const auto& [d2, j] : near) {
          if (d2 > 4 * reach2) break;  // the bisector lies beyond every corner
          const Vec3d& sj = g.position[size_t(j)];
          if (cell.clip(sj - s, 0.5 * (dot(sj, sj) - dot(s, s)), j)) {
            const double m = cell.max_distance(s);
            reach2 = m * m;
          }
        }
        done2 = radius * radius;
      }
      clipper.measure(i, s, cell, results[size_t(i)]);
    }
  }

  clock.lap("cells (clip + volume)");
  // Gather: volumes, cells, adjacency (faces inside the solid, from either side). Offsets
  // first, then every cell copied into its place in parallel.
  g.volume.resize(n);
  VoronoiCells& cells = g.cells;
  cells.surface = solid;
  cells.cube_half_side = rho;
  cells.face_offset.assign(n + 1, 0);
  cells.triangle_offset.assign(n + 1, 0);
  std::vector<int64_t> pair_offset(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    cells.face_offset[i + 1] = cells.face_offset[i] + int64_t(results[i].faces.size());
    cells.triangle_offset[i + 1] = cells.triangle_offset[i] + int64_t(results[i].triangles.size());
    pair_offset[i + 1] = pair_offset[i] + int64_t(results[i].adjacent.size());
  }
  cells.face_site.resize(size_t(cells.face_offset[n]));
  cells.triangles.resize(size_t(cells.triangle_offset[n]));
  std::vector<std::pair<int32_t, int32_t>> pairs(static_cast<size_t>(pair_offset[n]));
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < int64_t(n); ++i) {
    CellResult& c = results[size_t(i)];
    g.volume[size_t(i)] = c.volume;
    std::copy(c.faces.begin(), c.faces.end(), cells.face_site.begin() + cells.face_offset[size_t(i)]);
    std::copy(c.triangles.begin(), c.triangles.end(),
              cells.triangles.begin() + cells.triangle_offset[size_t(i)]);
    for (size_t k = 0; k < c.adjacent.size(); ++k)
      pairs[size_t(pair_offset[size_t(i)]) + k] = {int32_t(i), c.adjacent[k]};
    c = CellResult{};
  }
  g.adjacency = adjacency_from_pairs(n, std::move(pairs));
  clock.lap("gather + adjacency");
  compute_lambda(g);
  clock.lap("nearest distances");
  return g;
}

}  // namespace pd
