// Checks that a triangle mesh bounds a solid, and the repairs a scene may ask for. Every
// refusal is a MeshError naming the file, what is wrong (with counts) and what is allowed.
#pragma once

#include <string>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

// How near, relative to the bounding box's diagonal, vertices merged by weld_near are.
constexpr double kWeldDistance = 1e-6;

struct MeshCheckOptions {
  bool fill_holes = false;  // close simple boundary loops by a fan around their centroid
  // Whether the caller takes repair = "fill_holes" (a body's mesh), which an open mesh's message
  // then offers; elsewhere it asks for a closed mesh.
  bool repair_offered = false;
  // Merge vertices within kWeldDistance of the bounding box's diagonal of each other (a mesh whose
  // faces were exported apart, their corners a round-off from each other).
  bool weld_near = false;
};

// What the check changed, one line each (e.g. "filled 5 holes (boundary loops)").
struct MeshReport {
  int holes = 0;            // boundary loops found (and filled when fill_holes)
  bool flipped = false;     // the orientation was inverted and has been flipped
  int welded_vertices = 0;  // vertices merged with an identical earlier one
  std::vector<std::string> notes;
};

// In order: a non-empty mesh; finite coordinates; bit-identical vertices merged; no degenerate
// triangle (a repeated corner or zero area); every edge shared by at most two triangles (else
// non-manifold) with opposite directions (else inconsistent orientation); no boundary (an open
// mesh is refused with its boundary-loop count unless fill_holes closes them); a non-zero volume,
// outward (a negative signed volume is flipped and reported). `path` names the mesh in messages.
MeshReport check_solid(TriMesh& mesh, const std::string& path, const MeshCheckOptions& options);

// Boundary loops of a mesh (each as its vertex cycle, following the triangles' direction), for
// reports and tests. Throws MeshError when a boundary vertex starts two loops (not simple), its
// message offering repair = "fill_holes" with `repair_offered` (MeshCheckOptions).
std::vector<std::vector<int32_t>> boundary_loops(const TriMesh& mesh, const std::string& path,
                                                 bool repair_offered = false);

}  // namespace pd
