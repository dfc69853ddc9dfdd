// The run's tetrahedra file `tets.ptt`: the rest-space tet meshes of every tet and shell body
// (the embedded mesh of Chen sec. 5.2, one tet per particle), written once at the start of a run
// so that `perifrac render` draws those bodies as their tetrahedra, each placed by its fragment's
// rigid transform. Little-endian binary, float32 vertices; docs/output-formats.md documents the
// byte layout.
#pragma once

#include <string>

#include "host/fragments/embedded_mesh.h"

namespace pd {

inline constexpr char kTetsMagic[8] = {'P', 'T', 'E', 'T', 'M', 'E', 'S', 'H'};
inline constexpr uint32_t kTetsVersion = 1;
inline constexpr const char* kTetsFileName = "tets.ptt";

// Writes atomically; throws IoError when the file cannot be written.
void write_tets_file(const std::string& path, const EmbeddedTets& tets);

// Validates magic, version, the counts against the file length, vertex indices and particle
// indices; throws IoError "cannot read '<path>': <what is wrong>" on any problem. Vertices come
// back as the float32 values stored.
EmbeddedTets read_tets_file(const std::string& path);

}  // namespace pd
