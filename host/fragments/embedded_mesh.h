// Chen et al.'s embedded mesh (sec. 5.2), for every kind of element: the polygon complex of the
// particles' cubes, tets or Voronoi cells (element_complex.h), split along the cracks as bonds
// break and moved with the particles, so its boundary is the object's surface plus the crack
// surfaces. Per frame it gives that split surface (crack_mesh_file.h writes it as OBJ and PLY).
#pragma once

#include <cstdint>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/fragments/align.h"
#include "host/fragments/components.h"
#include "host/fragments/crack_mesh_file.h"
#include "host/fragments/element_complex.h"
#include "host/fragments/face_links.h"
#include "host/fragments/tet_complex.h"  // EmbeddedTets, which the scene set-up keeps for tet bodies
#include "host/geometry/element_adjacency.h"
#include "host/geometry/vec3d.h"

namespace pd {

class EmbeddedMesh {
 public:
  // `complex`: the elements, element p standing for particle p (assemble()). `adjacency`: the
  // adjacent elements whose bond holds fragments together (components.h); faces between elements
  // that are not adjacent there never hold (a crack from the start). `bonds`: the families as
  // built; `rest`, `mass`: the particles' rest positions and masses. Touching elements farther apart
  // than the horizon are held by their common neighbours (face_links.h). Throws
  // std::invalid_argument when sizes differ.
  EmbeddedMesh(ElementComplex complex, const ElementAdjacency& adjacency, const BondLists& bonds,
               std::vector<Vec3> rest, std::vector<real> mass);

  // One frame: adds the faces whose bond is now broken (in either family) to the crack-face set,
  // splits the vertices they separate, then places every vertex copy by its particles (eqs. 19-21
  // in the fragment's rotating frame, see update's comment). `position`: the particles' current
  // positions; `c` and `fits`: the frame's fragments and their rigid fits (align_fragments).
  // Throws std::invalid_argument on a size mismatch.
  void update(const BondLists& bonds, const std::vector<Vec3>& position, const Components& c,
              const std::vector<Fragment>& fits);

  // The current split surface (only the vertices it uses, numbered in order of first use);
  // polygons are cut into fans of triangles.
  void surface(CrackSurface& out) const;
  CrackSurface surface() const;

  const ElementComplex& elements() const { return complex_; }  // in rest space, as given
  size_t element_count() const { return complex_.size(); }
  size_t original_vertex_count() const { return complex_.vertices.size(); }
  size_t vertex_count() const { return position_.size(); }  // after splitting
  // Cracked element pairs: all whose bond broke; open: those a vertex split separated (drawn).
  size_t crack_face_count() const { return crack_pairs_; }
  size_t open_crack_face_count() const { return open_pairs_; }

 private:
  void split(int32_t v);
  void place_at_rest(int32_t v);  // frame_ of v's copies

  ElementComplex complex_;
  std::vector<real> mass_;
  std::vector<Vec3> rest_;               // particle rest positions
  std::vector<int32_t> corner_element_;  // per corner: its element
  // Corners at original vertex v: incident_[incident_start_[v] .. incident_start_[v + 1]), and,
  // stored alongside for the per-frame pass over the vertices, each one's element, copy (the same
  // as corner_copy_) and weight m_p / (corners of the element).
  std::vector<int64_t> incident_start_;
  std::vector<int64_t> incident_;
  std::vector<int32_t> incident_element_, incident_copy_;
  std::vector<double> incident_weight_;
  // Element pairs that share faces: the two elements, what holds them, and the state: 0 intact,
  // 1 crack, 2 crack opened by a split.
  std::vector<std::array<int32_t, 2>> pair_element_;
  FaceLinks links_;
  std::vector<uint8_t> pair_state_;
  std::vector<int64_t> face_pair_;  // per face: its pair, -1 on the object's surface
  // The pairs of element e: element_pair_[element_pair_start_[e] .. [e + 1]).
  std::vector<int64_t> element_pair_start_, element_pair_;
  size_t crack_pairs_ = 0, open_pairs_ = 0;
  size_t slots_ = 0;  // bond slots of the families
  // Vertex copies: the copy each corner uses now, and each copy's position.
  std::vector<int32_t> corner_copy_;
  std::vector<Vec3d> position_;
  // Per copy: its rest offset from the weighted centroid of its particles, the inverse of their
  // weight, and one of them (for the fragment whose rotation turns the offset).
  struct CopyFrame {
    Vec3d offset;
    double inv_weight;
    int32_t particle;
  };
  std::vector<CopyFrame> frame_;
  // Scratch of update and split.
  std::vector<int32_t> dirty_;
  std::vector<uint8_t> is_dirty_, newly_;
  std::vector<int32_t> local_, group_parent_, group_copy_, claimed_;
  std::vector<Vec3d> now_;  // per copy: the weighted sum of its particles' current positions
};

}  // namespace pd
