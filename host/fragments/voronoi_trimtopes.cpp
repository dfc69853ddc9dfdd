#include "host/fragments/voronoi_trimtopes.h"

#include <stdexcept>
#include <string>

#include "host/geometry/convex_cell.h"

namespace pd {

namespace {

// Is p inside the object: no triangle on the segment p -> site, or a backward-facing one first
// (the secondary ray of Levine Fig. 4, in double).
bool inside_object(const RestTrimtopes& r, size_t i, const Vec3d& p) {
  const Vec3d d = r.site[i] - p;
  double best = 2;
  bool inside = true;
  for (int64_t k = r.tri_start[i]; k < r.tri_start[i + 1]; ++k) {
    const Vec3d& a = r.tri_vertex[size_t(3 * k)];
    const Vec3d e1 = r.tri_vertex[size_t(3 * k + 1)] - a, e2 = r.tri_vertex[size_t(3 * k + 2)] - a;
    const Vec3d h = cross(d, e2);
    const double det = dot(e1, h);
    if (det == 0) continue;
    const Vec3d s = p - a;
    const double u = dot(s, h) / det;
    const Vec3d q = cross(s, e1);
    const double v = dot(d, q) / det;
    const double t = dot(e2, q) / det;
    if (u < 0 || v < 0 || u + v > 1 || t <= 0 || t >= 1 || t >= best) continue;
    best = t;
    inside = dot(cross(e1, e2), d) > 0;
  }
  return inside;
}

}  // namespace

RestTrimtopes rest_trimtopes(const ParticleGeometry& g, int32_t first_particle) {
  const VoronoiCells& c = g.cells;
  const size_t n = g.size();
  if (g.kind != ElementKind::voronoi || c.face_offset.size() != n + 1 || c.triangle_offset.size() != n + 1)
    throw std::invalid_argument("trimtopes need Voronoi cells, one per particle (got " +
                                std::to_string(c.face_offset.size()) + " cell offsets for " +
                                std::to_string(n) + " particles)");
  RestTrimtopes r;
  r.particle.resize(n);
  for (size_t i = 0; i < n; ++i) r.particle[i] = first_particle + int32_t(i);
  r.site = g.position;
  r.box.resize(n);
  const double rho = c.cube_half_side;
  std::vector<Vec3d> poly, scratch;
  for (size_t i = 0; i < n; ++i) {
    const Vec3d& s = g.position[i];
    // The cell: the cube around the site cut by the bisector planes of its neighbours, in the
    // order the geometry stage found them; a box side (id < 0) is a plane of that cube.
    ConvexCell cell(s - Vec3d{rho, rho, rho}, s + Vec3d{rho, rho, rho});
    for (int64_t k = c.face_offset[i]; k < c.face_offset[i + 1]; ++k) {
      const int32_t j = c.face_site[size_t(k)];
      Vec3d normal{0, 0, 0};
      double offset;
      if (j >= 0) {
        const Vec3d& sj = g.position[size_t(j)];
        normal = sj - s;
        offset = 0.5 * (dot(sj, sj) - dot(s, s));
        cell.clip(normal, offset, j);
      } else {
        const int side = -1 - j, axis = side / 2;
        const bool high = side % 2 == 1;
        normal[size_t(axis)] = high ? 1 : -1;
        offset = high ? s[size_t(axis)] + rho : -(s[size_t(axis)] - rho);
      }
      const double len = norm(normal);
      r.plane_normal.push_back((1 / len) * normal);
      r.plane_offset.push_back(offset / len);
    }
    r.plane_start.push_back(int64_t(r.plane_normal.size()));
    for (int64_t k = c.triangle_offset[i]; k < c.triangle_offset[i + 1]; ++k) {
      const Triangle& t = c.surface.triangles[size_t(c.triangles[size_t(k)])];
      for (int32_t v : t) r.tri_vertex.push_back(c.surface.vertices[size_t(v)]);
    }
    r.tri_start.push_back(int64_t(r.tri_vertex.size() / 3));

    // Bounds of the solid part: the cell's corners inside the object and the surface triangles
    // clipped to the cell (they hold every point where the surface crosses a cell edge).
    Box3d& box = r.box[i];
    for (const ConvexCell::Face& f : cell.faces())
      for (int32_t v : f.corners)
        if (r.tri_start[i] == r.tri_start[i + 1] || inside_object(r, i, cell.corner(v)))
          box.add(cell.corner(v));
    for (int64_t k = r.tri_start[i]; k < r.tri_start[i + 1]; ++k) {
      poly.assign(r.tri_vertex.begin() + 3 * k, r.tri_vertex.begin() + 3 * k + 3);
      for (const ConvexCell::Face& f : cell.faces()) {
        clip_polygon(poly, f.normal, f.offset, scratch);
        if (poly.empty()) break;
      }
      for (const Vec3d& p : poly) box.add(p);
    }
    if (!(box.lo[0] <= box.hi[0])) box.add(s);  // degenerate: keep a point box at the site
  }
  return r;
}

void append(RestTrimtopes& all, const RestTrimtopes& more) {
  auto shifted = [](std::vector<int64_t>& to, const std::vector<int64_t>& from) {
    const int64_t base = to.back();
    for (size_t k = 1; k < from.size(); ++k) to.push_back(base + from[k]);
  };
  all.particle.insert(all.particle.end(), more.particle.begin(), more.particle.end());
  all.site.insert(all.site.end(), more.site.begin(), more.site.end());
  shifted(all.plane_start, more.plane_start);
  all.plane_normal.insert(all.plane_normal.end(), more.plane_normal.begin(), more.plane_normal.end());
  all.plane_offset.insert(all.plane_offset.end(), more.plane_offset.begin(), more.plane_offset.end());
  shifted(all.tri_start, more.tri_start);
  all.tri_vertex.insert(all.tri_vertex.end(), more.tri_vertex.begin(), more.tri_vertex.end());
  all.box.insert(all.box.end(), more.box.begin(), more.box.end());
}

int32_t add_placed_trimtope(PrimitiveSet* prims, const RestTrimtopes& rest, size_t i,
                            const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  auto place = [&](const Vec3d& p) {
    const Eigen::Vector3d q = rotation * Eigen::Vector3d(p[0], p[1], p[2]) + translation;
    return Vec3{real(q.x()), real(q.y()), real(q.z())};
  };
  // Planes: n' = R n, offset' = offset + n'.t (exact negatives stay exact negatives).
  const int64_t p0 = rest.plane_start[i], p1 = rest.plane_start[i + 1];
  Vec3 normal[64];
  real offset[64];
  std::vector<Vec3> many_normals;
  std::vector<real> many_offsets;
  Vec3* nn = normal;
  real* oo = offset;
  if (p1 - p0 > 64) {
    many_normals.resize(size_t(p1 - p0));
    many_offsets.resize(size_t(p1 - p0));
    nn = many_normals.data();
    oo = many_offsets.data();
  }
  for (int64_t k = p0; k < p1; ++k) {
    const Vec3d& m = rest.plane_normal[size_t(k)];
    const Eigen::Vector3d rn = rotation * Eigen::Vector3d(m[0], m[1], m[2]);
    nn[k - p0] = {real(rn.x()), real(rn.y()), real(rn.z())};
    oo[k - p0] = real(rest.plane_offset[size_t(k)] + rn.dot(translation));
  }
  // Triangles, and the bounds: the rest box's corners moved.
  const int64_t t0 = rest.tri_start[i], t1 = rest.tri_start[i + 1];
  std::vector<Vec3> tri(size_t(3 * (t1 - t0)));
  for (int64_t k = 3 * t0; k < 3 * t1; ++k) tri[size_t(k - 3 * t0)] = place(rest.tri_vertex[size_t(k)]);
  const Box3d& rb = rest.box[i];
  Box box{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 q = place({(corner & 1) ? rb.hi[0] : rb.lo[0], (corner & 2) ? rb.hi[1] : rb.lo[1],
                          (corner & 4) ? rb.hi[2] : rb.lo[2]});
    box.lo = vmin(box.lo, q);
    box.hi = vmax(box.hi, q);
  }
  return prims->add_trimtope(place(rest.site[i]), nn, oo, int32_t(p1 - p0), tri.data(), int32_t(t1 - t0),
                             box);
}

}  // namespace pd
