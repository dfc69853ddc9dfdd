// One frame of a run as raytracer primitives (Levine sec. 5: every particle is the base point of
// a solid primitive). Particles of Voronoi bodies become their trimtopes (trimtopes.ptm),
// particles of tet and shell bodies their tetrahedra (tets.ptt), every other particle a cube of
// side cbrt(rest volume). Rest-space geometry is placed by its fragment's rigid transform
// (fragments_NNNNN.pfg): trimtopes and tetrahedra moved, cubes moved and turned (oriented cubes).
// Without a fragment, a particle's geometry moves by its displacement and a cube stays
// axis-aligned at the particle's current position.
#pragma once

#include <vector>

#include "host/fragments/embedded_mesh.h"
#include "host/fragments/fragments_file.h"
#include "host/fragments/voronoi_trimtopes.h"
#include "host/io/frame.h"
#include "render/looks.h"
#include "render/primitive_set.h"

namespace pd {

// A fragment rotation no further than this from the identity in any entry places its cubes
// axis-aligned (below float resolution; keeps the faces of a resting lattice on shared planes).
constexpr double kAxisAlignedRotation = 1e-7;

// Primitives and albedos of one frame (not yet a kd-tree), in particle order: one primitive per
// particle, its albedo by its body's look. `trimtopes`, `tets` and `fragments` may be null. Throws
// std::invalid_argument when the frame, the trimtopes, the tets or the fragments do not match the rest file.
void frame_primitives(const RestData& rest, const FrameData& frame, PrimitiveSet* prims,
                      std::vector<Vec3>* albedo, const RestTrimtopes* trimtopes = nullptr,
                      const FragmentsFrame* fragments = nullptr, const EmbeddedTets* tets = nullptr,
                      const RunLooks& looks = RunLooks());

// Bounding box of the cubes of side cbrt(volume) centred at `positions`.
Box cube_bounds(const std::vector<Vec3>& positions, const std::vector<float>& volume);

}  // namespace pd
