// The artist controls of a scene as the engine takes them: [[cracks]] as cut triangles (quads,
// extruded polylines, random walks, meshes) and [[regions]] as per-particle strain limits.
#pragma once

#include <functional>
#include <vector>

#include "cuda/engine/cut_triangle.h"
#include "host/scene/scene.h"

namespace pd {

// Every crack of the scene as triangles, with its strength and body index. Random walks draw
// from the scene's seed. Throws SceneError for an unreadable crack mesh.
std::vector<CutTriangle> crack_triangles(const Scene& scene);

// The polyline of one random walk set: `walks` walks from `start` in the plane normal to
// `extrude`, leaving in evenly spread directions (jittered), each turning by up to +-turn per step.
std::vector<std::vector<Vec3d>> random_walks(const SceneCrack& crack, uint64_t seed);

// Tests whether a rest position lies in each region; one per [[regions]] entry. Throws
// SceneError for a region mesh that is unreadable or not closed.
std::vector<std::function<bool(const Vec3d&)>> region_tests(const Scene& scene);

}  // namespace pd
