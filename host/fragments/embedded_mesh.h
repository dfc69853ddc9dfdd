// Chen et al.'s embedded tetrahedral mesh (sec. 5.2): the tet mesh whose elements are the particles
// of tet bodies, split along the cracks as bonds break and moved with the particles, so its
// boundary is the object's surface plus the crack surfaces. Per frame it writes that split surface
// as OBJ and PLY with a per-face flag: crack face or original surface.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "../engine.h"
#include "../geometry/tet_mesh.h"
#include "../geometry/vec3d.h"

namespace pd {

// The tet meshes of all tet bodies of a scene in one: scene-space vertices, tets, and the particle
// each tet stands for (its barycentre). Bodies never share vertices.
struct EmbeddedTets {
  std::vector<Vec3d> vertices;               // rest positions [m]
  std::vector<std::array<int32_t, 4>> tets;  // vertex indices
  std::vector<int32_t> particle;             // per tet: its particle index in the scene

  bool empty() const { return tets.empty(); }
  // Adds one body's mesh whose tet t is particle first_particle + t.
  void append(const TetMesh& mesh, int32_t first_particle);
};

// A split surface: every face of a tet that has no tet on its other side any more, facing out of
// the material. Original-surface triangles come first, then the crack triangles.
struct CrackSurface {
  std::vector<Vec3d> vertices;                    // current positions [m]
  std::vector<std::array<int32_t, 3>> triangles;  // counter-clockwise seen from outside
  std::vector<uint8_t> crack;                     // per triangle: 1 on a crack, 0 on the original surface

  size_t crack_count() const;
};

class EmbeddedTetMesh {
 public:
  // `bonds`: the families as built. `rest`, `mass`: the particles' rest positions and masses.
  // Throws std::invalid_argument when an index is out of range, a face is shared by more than two
  // tets, two tets sharing a face stand for the same particle, or their particles share no family
  // bond in both directions.
  EmbeddedTetMesh(EmbeddedTets tets, const BondLists& bonds, std::vector<Vec3> rest, std::vector<real> mass);

  // One frame: adds the faces whose bond is now broken (in either family) to the crack-face set,
  // splits the vertices they separate, then moves every vertex with its particles (eqs. 19-21).
  // `position`: the particles' current positions. Throws std::invalid_argument on a size mismatch.
  void update(const BondLists& bonds, const std::vector<Vec3>& position);

  // The current split surface (only the vertices it uses, numbered in order of first use).
  void surface(CrackSurface& out) const;
  CrackSurface surface() const;

  size_t tet_count() const { return particle_.size(); }
  size_t original_vertex_count() const { return incident_start_.size() - 1; }
  size_t vertex_count() const { return position_.size(); }  // after splitting
  // Crack faces: all faces whose bond broke; open: those a vertex split separated (drawn).
  size_t crack_face_count() const { return crack_faces_; }
  size_t open_crack_face_count() const { return open_faces_; }

 private:
  void split(int32_t v);
  bool open(int64_t face) const;

  std::vector<std::array<int32_t, 4>> tet_;  // original vertex indices, positively oriented
  std::vector<int32_t> particle_;
  std::vector<real> mass_;
  std::vector<Vec3> previous_;  // particle positions at the last update (rest at first)
  // Corner 4 t + k of tet t: the vertex (copy) it uses now, and the interior face opposite it
  // (-1 on the original surface).
  std::vector<int32_t> corner_vertex_;
  std::vector<int64_t> corner_face_;
  // Corners 4 t + k at original vertex v: incident_[incident_start_[v] .. incident_start_[v + 1]).
  std::vector<int64_t> incident_start_, incident_;
  // Interior faces: the two tets' corners opposite the face, the bond slots of the pair in both
  // families, and the state: 0 intact, 1 crack face, 2 crack face opened by a split.
  std::vector<std::array<int64_t, 2>> face_corner_, face_slot_;
  std::vector<uint8_t> face_state_;
  size_t crack_faces_ = 0, open_faces_ = 0;
  // Vertices (copies): position and original vertex.
  std::vector<Vec3d> position_;
  std::vector<int32_t> original_;
  size_t slots_ = 0;  // bond slots of the families
  // Scratch of update and split.
  std::vector<int32_t> dirty_;
  std::vector<uint8_t> is_dirty_;
  std::vector<int32_t> local_, group_parent_, group_copy_, claimed_;
  std::vector<double> weight_;
  std::vector<Vec3d> shift_;
};

// "crack_mesh_00042.<extension>": a frame's crack mesh file in the output directory.
std::string crack_mesh_file_name(int64_t frame, std::string_view extension);

// Writers (atomic; IoError when the file cannot be written). `comment` goes into the header.
// OBJ: `v` lines, then the original surface as `g surface` / `usemtl surface` and the crack faces
// as `g crack` / `usemtl crack` (1-based triangle `f` lines).
void write_crack_obj(const std::string& path, const CrackSurface& s, const std::string& comment);
// PLY, binary little endian: vertex `float x y z`, face `list uchar int vertex_indices` and
// `uchar crack`.
void write_crack_ply(const std::string& path, const CrackSurface& s, const std::string& comment);

// Reads what the writers wrote (by extension, .obj or .ply; positions as stored). Throws MeshError
// for a file of another layout.
CrackSurface read_crack_mesh(const std::string& path);

}  // namespace pd
