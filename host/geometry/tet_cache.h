// TetGen's meshes kept between runs (tetgen.cpp): the same surface, inserted points and switches
// give the same tets, and a scene run again (another material, another frame count) need not
// wait for TetGen again; the vase at Levine's size spends 5 s of its set-up there. An entry is
// one file, tets-<key>.bin, named by a hash of TetGen's input files and switches, holding a
// second hash of them and a checksum of its contents: an entry that is not whole, or not this
// input's, is ignored and written again. The folder keeps at most kTetCacheBytes of entries: the
// ones used longest ago go first.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "host/geometry/tet_mesh.h"

namespace pd {

constexpr uint64_t kTetCacheBytes = uint64_t(4) << 30;

// The cache's folder: PERIFRAC_TET_CACHE (a folder, or "off"), else $XDG_CACHE_HOME/perifrac/tets,
// else $HOME/.cache/perifrac/tets; empty (no cache) when off or with none of them set.
std::string tet_cache_folder();

class TetCache {
 public:
  // `input`: every byte TetGen reads (its switches, then its input files); `bound`: the bytes of
  // entries the folder keeps.
  TetCache(std::string folder, std::string_view input, uint64_t bound = kTetCacheBytes);

  // The entry's mesh, or none (missing, not whole, or another input's).
  std::optional<TetMesh> load() const;
  // Writes the entry (whole or not at all) and trims the folder to its bound. A cache that
  // cannot be written is said once on stderr; the caller goes on without it.
  void store(const TetMesh& mesh) const;

  const std::string& path() const { return path_; }

 private:
  std::string folder_, path_;
  uint64_t check_ = 0;  // the second hash of the input, kept in the entry
  uint64_t bound_ = kTetCacheBytes;
};

}  // namespace pd
