#include "host/fragments/piece_mesh.h"

#include <stdexcept>
#include <string>

#include "host/fragments/obj_text.h"
#include "host/io/atomic_file.h"

namespace pd {

FragmentMesh fragment_pieces(const ElementComplex& complex, const Components& c) {
  if (complex.size() != c.id.size())
    throw std::invalid_argument("fragment_pieces: " + std::to_string(complex.size()) + " elements for " +
                                std::to_string(c.id.size()) + " particles");
  // Each fragment: the faces of its elements not shared with an element of the same fragment,
  // with the vertices renumbered per object in order of first use.
  FragmentMesh mesh;
  std::vector<int32_t> local(complex.vertices.size(), -1);
  std::vector<int32_t> used;
  for (size_t k = 0; k < c.count(); ++k) {
    for (int32_t m = c.start[k]; m < c.start[k + 1]; ++m) {
      const size_t e = size_t(c.members[size_t(m)]);
      for (int64_t f = complex.face_start[e]; f < complex.face_start[e + 1]; ++f) {
        const int32_t other = complex.face_other[size_t(f)];
        if (other >= 0 && c.index[size_t(other)] == int32_t(k)) continue;
        for (int64_t q = complex.face_corner_start[size_t(f)]; q < complex.face_corner_start[size_t(f) + 1];
             ++q) {
          const int32_t v = complex.corner_vertex[size_t(complex.face_corner[size_t(q)])];
          if (local[size_t(v)] < 0) {
            local[size_t(v)] = int32_t(mesh.vertices.size());
            mesh.vertices.push_back(complex.vertices[size_t(v)]);
            used.push_back(v);
          }
          mesh.polygon_vertex.push_back(local[size_t(v)]);
        }
        mesh.polygon_start.push_back(int64_t(mesh.polygon_vertex.size()));
      }
    }
    for (int32_t v : used) local[size_t(v)] = -1;
    used.clear();
    mesh.ids.push_back(c.component_id(k));
    mesh.vertex_start.push_back(int64_t(mesh.vertices.size()));
    mesh.object_start.push_back(int64_t(mesh.polygons()));
  }
  return mesh;
}

void write_obj(const std::string& path, const FragmentMesh& mesh) {
  // Per object: its name, its vertices, its polygons (1-based indices into all vertices).
  std::vector<std::string> text{
      "# perifrac fragment surfaces in rest space [m], one object per fragment;\n"
      "# fragments_NNNNN.pfg holds each fragment's transform per frame (docs/fragments.md)\n"};
  append_lines(text, mesh.objects(), [&](std::string& out, size_t o) {
    out += "o fragment_" + std::to_string(mesh.ids[o]) + "\n";
    for (int64_t v = mesh.vertex_start[o]; v < mesh.vertex_start[o + 1]; ++v) {
      out += 'v';
      for (double x : mesh.vertices[size_t(v)]) append_coordinate(out, x);
      out += '\n';
    }
    for (int64_t q = mesh.object_start[o]; q < mesh.object_start[o + 1]; ++q) {
      out += 'f';
      for (int64_t k = mesh.polygon_start[size_t(q)]; k < mesh.polygon_start[size_t(q) + 1]; ++k)
        append_index(out, mesh.polygon_vertex[size_t(k)] + 1);
      out += '\n';
    }
  });
  write_parts_atomic(path, text);
}

}  // namespace pd
