// Surface mesh files: OBJ, PLY (ascii and binary little-endian) and STL (ascii and binary).
// Readers throw MeshError naming the file, the line or element, and what is allowed; they only
// parse: the checks of a usable solid (finite, non-degenerate, closed, ...) are in mesh_check.h.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

// Reads by extension (.obj, .ply, .stl, case-insensitive). Polygons are split into triangle fans.
TriMesh read_mesh(const std::string& path);

TriMesh read_obj(const std::string& path);
TriMesh read_ply(const std::string& path);
// STL stores each facet's own corners; identical corners are merged into one vertex.
TriMesh read_stl(const std::string& path);

// The same readers over a file's bytes already in memory (the read_* functions read the file and
// call these); `path` names the mesh in messages only.
TriMesh parse_obj(const std::string& bytes, const std::string& path);
TriMesh parse_ply(const std::string& bytes, const std::string& path);
TriMesh parse_stl(const std::string& bytes, const std::string& path);

// A text format's bytes without a UTF-8 byte-order mark at their start (an editor's mark).
std::string_view without_utf8_mark(const std::string& bytes);

// Writers (atomic: temporary file, then rename; IoError on failure).
void write_obj(const TriMesh& mesh, const std::string& path);
void write_ply(const TriMesh& mesh, const std::string& path, bool binary);
void write_stl(const TriMesh& mesh, const std::string& path, bool binary);

namespace detail {
// The whole file as bytes; MeshError when it cannot be read.
std::string read_file_bytes(const std::string& path);
// Text of a file quoted in a message: control characters as \xNN and at most 60 characters
// ("..." marks a cut), so every message stays one printable line.
std::string printable(std::string_view text);
// A polygon's triangles (its corners' positions already in `mesh`): a fan from the first corner
// whose triangles all have area, so that a corner lying on an edge between two others (a T
// junction a modeller left) makes no triangle of zero area; from the first corner where none does.
void add_polygon(TriMesh& mesh, const std::vector<int32_t>& polygon);
}  // namespace detail

}  // namespace pd
