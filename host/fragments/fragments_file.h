// The per-frame fragments file `fragments_NNNNN.pfg`: one fixed-size little-endian record per
// fragment (id, size, mass, centroids, the transform to render with as quaternion and matrix, the
// least-squares fit, residual). docs/fragments.md documents the byte layout.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/fragments/align.h"

namespace pd {

inline constexpr char kFragmentsMagic[8] = {'P', 'F', 'R', 'A', 'G', 'S', '\0', '\0'};
inline constexpr uint32_t kFragmentsVersion = 1;
inline constexpr size_t kFragmentsHeaderBytes = 48;
inline constexpr size_t kFragmentRecordBytes = 280;

// "fragments_00042.pfg": the name of a frame's fragments file inside the output directory.
std::string fragments_file_name(int64_t frame);

struct FragmentsFrame {
  int64_t frame = 0;  // output frame number
  int64_t step = 0;   // simulation step
  double time = 0;    // simulated time [s]
  std::vector<Fragment> fragments;
};

// Writes atomically (write_file_atomic); throws IoError when the file cannot be written.
void write_fragments_file(const std::string& path, int64_t frame, int64_t step, double time,
                          const std::vector<Fragment>& fragments);

// Validates magic, version, record size and the file length; throws IoError
// "cannot read '<path>': <what is wrong>" on any problem.
FragmentsFrame read_fragments_file(const std::string& path);

}  // namespace pd
