// Per-frame particle points as PLY (binary little endian) for Blender, Houdini, MeshLab and
// ParaView: one vertex per particle at its current position with its velocity, damage, body and
// fragment id as extra vertex properties. docs/fragments.md lists the properties.
#pragma once

#include <cstdint>
#include <string>

#include "host/io/frame.h"

namespace pd {

// "points_00042.ply": the name of a frame's point file inside the output directory.
std::string points_file_name(int64_t frame);

// Writes `f` atomically: float x y z vx vy vz damage, int body, and int component when `f` has
// it; frame, step and time go into comment lines. Throws std::invalid_argument for inconsistent
// sizes, IoError when the file cannot be written.
void write_ply_points(const std::string& path, const FrameData& f);

// Reads a binary little-endian PLY whose first element is `vertex` with float or int scalar
// properties (the files write_ply_points writes, or the same data from another tool): x y z are
// required, vx vy vz, damage, body and component are read when present (missing ones read as 0,
// component as empty). Throws IoError naming the file and the problem.
FrameData read_ply_points(const std::string& path);

}  // namespace pd
