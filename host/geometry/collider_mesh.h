// A collider's surface as a closed triangle mesh, for the ParaView and Blender outputs and the
// renderer: in its shape frame (the frame `colliders_NNNNN.csv` poses) or posed in the world.
#pragma once

#include <string>
#include <vector>

#include "cuda/views.h"
#include "host/geometry/tri_mesh.h"

namespace pd {

// The shape's surface (y the axis of the round shapes, as in colliders.h) with edges of about
// `edge`; a plane as the square of half side `plane_half` in its x-z plane, facing +y.
TriMesh collider_mesh(const Collider& c, double edge, double plane_half);

// The mesh moved to the collider's pose: x -> R x + centre.
TriMesh posed_mesh(const TriMesh& shape, const Collider& c);

// `colliders.obj`: each collider's surface in its frame as an object `collider_K`, written
// atomically; and read back (one mesh per object, in order). read_collider_obj throws MeshError
// for a malformed file.
void write_collider_obj(const std::vector<TriMesh>& shapes, const std::string& path);
std::vector<TriMesh> read_collider_obj(const std::string& path);

}  // namespace pd
