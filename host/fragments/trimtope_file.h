// The run's trimtopes file `trimtopes.ptm`: the rest-space trimtopes of every Voronoi body
// (voronoi_trimtopes.h), written once at the start of a run so `perifrac render` can draw them.
// Little-endian binary, float32 geometry; docs/output-formats.md documents the byte layout.
#pragma once

#include <string>

#include "host/fragments/voronoi_trimtopes.h"

namespace pd {

inline constexpr char kTrimtopesMagic[8] = {'P', 'T', 'R', 'I', 'M', 'T', 'O', 'P'};
inline constexpr uint32_t kTrimtopesVersion = 1;
inline constexpr const char* kTrimtopesFileName = "trimtopes.ptm";

// Writes atomically; throws IoError when the file cannot be written.
void write_trimtopes_file(const std::string& path, const RestTrimtopes& t);

// Validates magic, version, every count against the file length and the CSR offsets; throws
// IoError "cannot read '<path>': <what is wrong>" on any problem.
RestTrimtopes read_trimtopes_file(const std::string& path);

}  // namespace pd
