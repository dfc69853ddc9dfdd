// `perifrac bench-render`: times the raytracer on a synthetic scene at a given resolution: the
// kd-tree build (serial and parallel), the render on a backend (primary and all rays per
// second), the same primary rays traced without shading on the CPU, and, when Embree is built
// in, Embree's single-ray (rtcIntersect1) throughput on the same primitives triangulated.
// A benchmark, not a test: results go to bench/results/ as JSON with the device, date and git
// revision.
#pragma once

#include <cstdint>
#include <string>

namespace pd {

struct RenderBenchOptions {
  std::string scene = "slab";  // slab (tetrahedra) | cubes | turned-cubes
  int64_t count = 600000;      // primitives wanted (the lattice rounds it)
  int width = 1920, height = 1080;
  int spp = 1;
  std::string material = "opaque";  // opaque | glass
  std::string backend = "auto";
  int repeat = 5;      // timed renders after one warm-up; the best is reported
  bool embree = true;  // Embree baseline (when built in)
  int fragments = 0;   // > 0: also measure the two-level prototype with this many fragments
  // kd-tree build knobs (KdBuildOptions); negative: the default.
  double kd_intersect_cost = -1;
  int kd_max_depth = -1;
  int kd_leaf_prims = -1;
  bool keep_hidden = false;  // every tetrahedron in the kd-tree (HiddenElements::kKeep)
  std::string out = "bench/results";
};

int bench_render_command(const RenderBenchOptions& options);

}  // namespace pd
