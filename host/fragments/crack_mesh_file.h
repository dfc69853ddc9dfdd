// The per-frame crack mesh files (Chen sec. 5.2): the split surface of the embedded mesh, original
// surface and crack surfaces, as OBJ and PLY with a per-face flag, and their reader.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "host/geometry/vec3d.h"

namespace pd {

// A split surface: every element face that has no element on its other side any more, facing out
// of the material. Original-surface triangles come first, then the crack triangles.
struct CrackSurface {
  std::vector<Vec3d> vertices;                    // current positions [m]
  std::vector<std::array<int32_t, 3>> triangles;  // counter-clockwise seen from outside
  std::vector<uint8_t> crack;                     // per triangle: 1 on a crack, 0 on the original surface
  // Per triangle: the particle whose element the face belongs to; empty where unknown (an OBJ file,
  // or a PLY file written before the property existed).
  std::vector<int32_t> particle;

  size_t crack_count() const;
};

// "crack_mesh_00042.<extension>": a frame's crack mesh file in the output directory.
std::string crack_mesh_file_name(int64_t frame, std::string_view extension);

// Writers (atomic; IoError when the file cannot be written). `comment` goes into the header.
// OBJ: `v` lines, then the original surface as `g surface` / `usemtl surface` and the crack faces
// as `g crack` / `usemtl crack` (1-based triangle `f` lines).
void write_crack_obj(const std::string& path, const CrackSurface& s, const std::string& comment);
// PLY, binary little endian: vertex `float x y z`, face `list uchar int vertex_indices`, `uchar
// crack` and `int particle` (-1 for every face when `s.particle` is empty).
void write_crack_ply(const std::string& path, const CrackSurface& s, const std::string& comment);

// Reads what the writers wrote (by extension, .obj or .ply; positions as stored), and PLY files
// without `int particle` (an empty `particle` then). Throws MeshError for a file of another layout.
CrackSurface read_crack_mesh(const std::string& path);

}  // namespace pd
