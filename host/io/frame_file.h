// The .pfr format: compact little-endian binary frames that later stages (fragment alignment,
// renderer) read fast. One layout, two kinds: a rest file (reference configuration, written
// once per run as `rest.pfr`) and frame files (`frame_NNNNN.pfr`, see frame_file_name).
// docs/output-formats.md documents the byte layout.
#pragma once

#include <cstdint>
#include <string>

#include "host/io/frame.h"

namespace pd {

inline constexpr char kPfrMagic[8] = {'P', 'F', 'R', 'A', 'M', 'E', '\0', '\0'};
inline constexpr uint32_t kPfrVersion = 1;
inline constexpr uint32_t kPfrKindRest = 0;
inline constexpr uint32_t kPfrKindFrame = 1;
inline constexpr uint32_t kPfrFloat32 = 1;  // array element types
inline constexpr uint32_t kPfrInt32 = 2;
inline constexpr const char* kRestFileName = "rest.pfr";

// Writers: atomic (see write_file_atomic). Throw std::invalid_argument for inconsistent array
// sizes and IoError when the file cannot be written.
void write_frame_file(const std::string& path, const FrameData& f);
void write_rest_file(const std::string& path, const RestData& r);

// Readers: validate magic, version, kind, every size against the file length, and the required
// arrays; throw IoError "cannot read '<path>': <what is wrong>" on any problem. Arrays with
// unknown names are skipped. A frame file without `component` reads back with it empty.
FrameData read_frame_file(const std::string& path);
RestData read_rest_file(const std::string& path);

}  // namespace pd
