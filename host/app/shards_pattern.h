// Shards along a finished run's cracks ([[shards]] `pattern`, issue 31): a second pass that keeps
// the crack pattern of a first run of the same scene and turns its dust into pieces.
#pragma once

#include <cstdint>

#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

// For each [[shards]] table with a `pattern`: reads the checkpoint in that folder (a run of this
// scene at this scale that wrote one, `perifrac run --checkpoint-every N`), checks that it was
// made from the particles `setup` holds, restores it on the CPU and reads which bonds it broke.
// Then every strain limit of the table's bodies and their compression strengthening are raised
// by `hold`, and the broken bonds become faces that keep the material's limit
// (SimulationInput::face_bonds, the particles' shard strength), except between particles of one
// dust cell: the first run's pieces of fewer than kPatternPieceParticles particles are grouped
// into Voronoi cells of `size` (seeds as ShardSeeds), which hold. Cracks then run where the first
// run's ran, and what crumbled there breaks into cells. Throws SceneError naming
// shards[N].pattern for a folder without a readable checkpoint or one made from other particles.
// Fills setup.pattern.
void apply_shards_pattern(const Scene& scene, SetupResult& setup, double scale);

// setup_scene with the patterns applied: the set-up of `perifrac run`, `bench` and `profile`.
SetupResult setup_scene_with_patterns(const Scene& scene, const SetupOptions& options);
SetupResult setup_scene_with_patterns(const Scene& scene, double scale, Backend backend);

}  // namespace pd
