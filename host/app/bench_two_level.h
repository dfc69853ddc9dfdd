// The two-level prototype measured by `perifrac bench-render --fragments F` (docs/rendering.md,
// "Per-frame rebuild or two levels"): the bench scene cut into F blocks, each moved by its own
// rigid transform as fragments are after fracture. Per frame, the renderer either rebuilds one
// kd-tree over the moved primitives (what it does), or keeps one tree per fragment in rest space
// and builds only a top-level tree over the fragments' moved bounds, tracing rays into each
// fragment's rest frame. Host only (the rays traced on the CPU without shading); both ways are
// timed and their hits compared.
#pragma once

#include <cstdint>
#include <vector>

#include "render/camera.h"
#include "render/kdtree.h"
#include "render/primitive_set.h"

namespace pd {

struct TwoLevelReport {
  int32_t fragments = 0;
  double rest_build_seconds = 0;   // all per-fragment trees in rest space (once per fragment)
  double top_build_seconds = 0;    // the top-level tree over the fragments' bounds (per frame)
  double world_build_seconds = 0;  // one tree over the moved primitives (per frame)
  double world_trace_seconds = 0, two_level_trace_seconds = 0;  // primary rays, pixel centres
  double instances_per_ray = 0;                                 // fragment trees entered per ray (two levels)
  double agreement = 0;  // pixels with the same hit or miss and depth within 1e-4
};

// Fraction of pixels whose hit or miss agrees and whose depths agree within 1e-4 relative, of two
// depth images (INFINITY: a miss).
double depth_agreement(const std::vector<float>& a, const std::vector<float>& b);

// `cells_x`, `cells_z`: the scene's lattice cells along x and z; `per_cell`: consecutive
// primitives per cell (cells in x, then y, then z order, `cells_y` layers). Cells are grouped
// into about `fragments` blocks in x and z.
TwoLevelReport measure_two_level(const PrimitiveSet& rest, int64_t cells_x, int64_t cells_y, int64_t cells_z,
                                 int per_cell, int fragments, const CameraFrame& camera,
                                 const KdBuildOptions& options);

}  // namespace pd
