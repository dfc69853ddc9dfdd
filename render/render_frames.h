// `perifrac render DIR`: turn the frames of a run into images. A particle of a Voronoi body
// becomes its trimtope (DIR/trimtopes.ptm), placed by its fragment's rigid transform
// (DIR/fragments_NNNNN.pfg) or, without one, moved by the particle's displacement; every other
// particle becomes a cube of side cbrt(rest volume) at its current position (axis-aligned).
// Colour by body, tinted by damage; the camera frames the rest configuration.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "../host/fragments/fragments_file.h"
#include "../host/io/frame.h"
#include "renderer.h"
#include "voronoi_trimtopes.h"

namespace pd {

struct RenderOptions {
  std::string dir;               // run output: DIR/rest.pfr and DIR/frame_*.pfr
  std::string out;               // image folder; empty: DIR/render
  std::string backend = "auto";  // auto | cpu | cuda
  int width = 1280, height = 720;
  int spp = 4;
  // Camera; by default a 3/4 view from above framing the rest bounding box.
  std::optional<Vec3> eye, look_at;
  real vfov_degrees = 35;
  bool floor = true;
  std::optional<real> floor_y;      // default: bottom of the lowest cube of the rest and last frames
  std::string material = "opaque";  // opaque | glass: the material of every body
  real ior = real(1.5);             // glass index of refraction
};

// Renders DIR/render/frame_NNNNN.png for every frame file, printing one line per frame with
// the rays per second. Returns kExitOk; throws IoError for unreadable or missing inputs and
// std::invalid_argument for bad options or frames that do not match the rest file.
int render_frames(const RenderOptions& options);

// The frame files of DIR (frame_*.pfr), in name order.
std::vector<std::string> list_frame_files(const std::string& dir);

// Linear RGB albedo of a particle of `body` with the given damage in [0, 1].
Vec3 particle_color(int32_t body, float damage);

// Primitives and albedos of one frame (not yet a kd-tree): the trimtope of each particle listed
// in `trimtopes` (may be null), placed by the transform of its fragment in `fragments` (may be
// null; then, or when the frame has no component ids, moved by its displacement); a cube for
// every other particle. Throws std::invalid_argument when the frame, the trimtopes or the
// fragments do not match the rest file.
void frame_primitives(const RestData& rest, const FrameData& frame, PrimitiveSet* prims,
                      std::vector<Vec3>* albedo, const RestTrimtopes* trimtopes = nullptr,
                      const FragmentsFrame* fragments = nullptr);

// Bounding box of the cubes of side cbrt(volume) centred at `positions`.
Box cube_bounds(const std::vector<Vec3>& positions, const std::vector<float>& volume);

}  // namespace pd
