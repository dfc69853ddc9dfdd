// Checkpoints of `perifrac run`: the full state after a frame, so a killed or interrupted run
// continues with `perifrac run --resume DIR` and produces what the uninterrupted run would have
// (bit for bit on the same backend, device and thread count). One file, <out>/checkpoint.pck,
// replaced atomically; a corrupted, truncated, foreign or incompatible file is refused.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/fragments/smoothing.h"
#include "host/io/vtk_writer.h"

namespace pd {

// A checkpoint that cannot be resumed from: missing, unreadable, or from another scene,
// scale or build. The message says which and what to do.
class ResumeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr const char* kCheckpointFileName = "checkpoint.pck";
inline constexpr uint32_t kCheckpointVersion = 2;

struct RunCheckpoint {
  // How the run was started; a resume repeats it.
  std::string scene_path;      // absolute
  std::string scene_relative;  // relative to the checkpoint's folder: found there when the two moved together
  std::vector<std::string> overrides;  // --set KEY=VALUE, in order
  uint64_t scene_hash = 0;             // scene_fingerprint of the file and the overrides
  uint64_t setup_hash = 0;  // setup_fingerprint: particles, materials, strain limits (seed, meshes)
  double scale = 1;
  int64_t steps_per_frame = 0, frames = 0;
  int blend_frames = 0;
  bool allow_unstable_dt = false;
  bool explicit_families = false;
  int64_t checkpoint_every = 0;  // --checkpoint-every and --checkpoint-minutes, kept by a resume
  double checkpoint_minutes = 10;
  std::string backend;  // where it ran
  // Where it stands.
  int64_t frame = 0;  // the last frame written
  EngineSnapshot engine;
  Energy energy0;            // the energy at frame 0, the watchdog's reference
  std::string energy_log;    // energy.csv up to `frame`
  std::string fragment_log;  // fragments.csv up to `frame` (empty from older checkpoints)
  std::vector<PvdSeries::Entry> series;
  FragmentSmoother::History smoother;
};

// Fingerprint of the particles set-up made of a scene: a change of mesh, seed or scale shows
// (material constants are covered by the scene file's own fingerprint).
uint64_t setup_fingerprint(const SimulationInput& in);
uint64_t file_fingerprint(const std::string& path);
// The scene file's bytes and the --set overrides applied to it.
uint64_t scene_fingerprint(const std::string& path, const std::vector<std::string>& overrides);

// Atomic; throws IoError naming the path.
void write_checkpoint(const std::string& path, const RunCheckpoint& c);
// Throws IoError "cannot read '<path>': <reason>" for a missing, corrupted, truncated, foreign or
// other-version file, or one written by a build of another precision.
RunCheckpoint read_checkpoint(const std::string& path);

}  // namespace pd
