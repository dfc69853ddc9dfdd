// Host-side owner of a primitive scene: the arrays behind a PrimitivesView.
#pragma once

#include <algorithm>
#include <vector>

#include "render/primitives.h"

namespace pd {

// The view of `n` primitives whose arrays `a` holds under PrimitiveSet's member names: a
// PrimitiveSet itself, or the renderer's copies of one on a device (anything whose arrays give
// their elements through data()).
template <class Arrays>
PrimitivesView primitives_view(int32_t n, const Arrays& a) {
  PrimitivesView v{n,
                   view_of(a.kind),
                   view_of(a.slot),
                   view_of(a.cube_center),
                   view_of(a.cube_half),
                   view_of(a.tet_vertex),
                   view_of(a.tet_plane),
                   view_of(a.ocube_center),
                   view_of(a.ocube_half),
                   view_of(a.ocube_axis),
                   view_of(a.tri_vertex),
                   view_of(a.tri_normal),
                   {}};
  v.trim = {view_of(a.trim_site),         view_of(a.trim_plane_start), view_of(a.trim_plane_normal),
            view_of(a.trim_plane_offset), view_of(a.trim_tri_start),   view_of(a.trim_tri_vertex),
            view_of(a.trim_box)};
  return v;
}

struct PrimitiveSet {
  std::vector<uint8_t> kind;
  std::vector<int32_t> slot;
  std::vector<Vec3> cube_center;
  std::vector<real> cube_half;
  std::vector<Vec3> tet_vertex;
  std::vector<TetPlane> tet_plane;  // 4 per tetrahedron (tet_planes)
  // Trimtopes (trimtope.h): CSR lists of face planes and surface triangles.
  std::vector<Vec3> trim_site;
  std::vector<int32_t> trim_plane_start{0};
  std::vector<Vec3> trim_plane_normal;
  std::vector<real> trim_plane_offset;
  std::vector<int32_t> trim_tri_start{0};
  std::vector<Vec3> trim_tri_vertex;
  std::vector<Box> trim_box;
  std::vector<Vec3> ocube_center;
  std::vector<real> ocube_half;
  std::vector<Vec3> ocube_axis;  // 3 per oriented cube
  std::vector<Vec3> tri_vertex;  // 3 per triangle
  std::vector<Vec3> tri_normal;  // 3 per triangle: the vertices' unit shading normals

  int32_t size() const { return int32_t(kind.size()); }

  // Each returns the new primitive's index.
  int32_t add_cube(Vec3 center, real half) {
    kind.push_back(kPrimCube);
    slot.push_back(int32_t(cube_center.size()));
    cube_center.push_back(center);
    cube_half.push_back(half);
    return size() - 1;
  }
  // A cube of half side `half` turned so that its local x, y, z axes are axis[0..2] (orthonormal,
  // e.g. the columns of a rotation matrix).
  int32_t add_oriented_cube(Vec3 center, real half, const Vec3 axis[3]) {
    kind.push_back(kPrimOrientedCube);
    slot.push_back(int32_t(ocube_center.size()));
    ocube_center.push_back(center);
    ocube_half.push_back(half);
    ocube_axis.insert(ocube_axis.end(), axis, axis + 3);
    return size() - 1;
  }
  // The four vertices are stored in lexicographic (x, y, z) order: tet_interval then computes a
  // face shared by two tetrahedra from the same vertices in the same order in both, so the two
  // get the same plane bit for bit and no ray slips between them.
  int32_t add_tet(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    kind.push_back(kPrimTet);
    slot.push_back(int32_t(tet_vertex.size() / 4));
    Vec3 v[4] = {a, b, c, d};
    std::sort(v, v + 4, [](Vec3 p, Vec3 q) {
      return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    });
    tet_vertex.insert(tet_vertex.end(), v, v + 4);
    tet_plane.resize(tet_plane.size() + 4);
    tet_planes(v, &tet_plane[tet_plane.size() - 4]);
    return size() - 1;
  }
  // A trimtope: site V, the cell's planes dot(normal[k], x) <= offset[k], `triangles` surface
  // triangles (3 vertices each, outward orientation) and a box holding its solid part.
  int32_t add_trimtope(Vec3 site, const Vec3* normal, const real* offset, int32_t planes,
                       const Vec3* triangle, int32_t triangles, const Box& box) {
    kind.push_back(kPrimTrimtope);
    slot.push_back(int32_t(trim_site.size()));
    trim_site.push_back(site);
    trim_plane_normal.insert(trim_plane_normal.end(), normal, normal + planes);
    trim_plane_offset.insert(trim_plane_offset.end(), offset, offset + planes);
    trim_plane_start.push_back(int32_t(trim_plane_normal.size()));
    trim_tri_vertex.insert(trim_tri_vertex.end(), triangle, triangle + 3 * int64_t(triangles));
    trim_tri_start.push_back(int32_t(trim_tri_vertex.size() / 3));
    trim_box.push_back(box);
    return size() - 1;
  }

  // A triangle a, b, c (counter-clockwise seen from outside the material) with unit shading
  // normals na, nb, nc at its vertices.
  int32_t add_triangle(Vec3 a, Vec3 b, Vec3 c, Vec3 na, Vec3 nb, Vec3 nc) {
    kind.push_back(kPrimTriangle);
    slot.push_back(int32_t(tri_vertex.size() / 3));
    tri_vertex.insert(tri_vertex.end(), {a, b, c});
    tri_normal.insert(tri_normal.end(), {na, nb, nc});
    return size() - 1;
  }
  // A flat triangle: its geometric normal at every vertex.
  int32_t add_triangle(Vec3 a, Vec3 b, Vec3 c) {
    const Vec3 v[3] = {a, b, c};
    const Vec3 n = triangle_normal(v);
    return add_triangle(a, b, c, n, n, n);
  }

  // A view of the host arrays (host-side tests and the kd-tree build).
  PrimitivesView view() const { return primitives_view(size(), *this); }

  std::vector<Box> bounds() const {
    std::vector<Box> b(kind.size());
    const PrimitivesView v = view();
    for (int32_t i = 0; i < size(); ++i) b[i] = primitive_bounds(v, i);
    return b;
  }
};

}  // namespace pd
