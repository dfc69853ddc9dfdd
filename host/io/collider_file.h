// `colliders_NNNNN.csv`: every collider's shape, size, pose and velocity at an output frame, one
// row each, so that the renderer draws them and Blender, ParaView or a spreadsheet can follow
// them. docs/output-formats.md documents the columns.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cuda/views.h"

namespace pd {

// One collider at a frame: as the engine holds it, and its mass (0: not a free body).
struct ColliderState {
  Collider collider;
  double mass = 0;
};

// "colliders_00042.csv".
std::string colliders_file_name(int64_t frame);

// Writes the file atomically; throws IoError when it cannot be written.
void write_colliders_file(const std::string& path, int64_t frame, double time,
                          const std::vector<ColliderState>& colliders);

// Reads one back (the rotation from its quaternion); throws IoError naming the file, the line and
// what is wrong for a missing or malformed file.
std::vector<ColliderState> read_colliders_file(const std::string& path);

// The rotation (row major, shape frame to world) as a unit quaternion w, x, y, z, and back.
std::array<double, 4> rotation_to_quaternion(const real* m);
void quaternion_to_rotation(const std::array<double, 4>& q, real* m);

}  // namespace pd
