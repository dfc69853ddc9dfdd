// The [render] block of a scene: `perifrac run` renders frames as it goes (render/live_render.h).
// Parsed by parse_render in scene_loader.cpp; documented in docs/scene-reference.md.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pd {

// [render.bodies.NAME]: how one body looks (render/looks.h).
struct SceneBodyLook {
  std::string body;                            // a [[bodies]] name
  std::string look;                            // a named look; empty: the body's default look
  std::optional<std::array<double, 3>> color;  // linear RGB in [0, 1], replacing the look's colour
};

struct SceneRender {
  std::optional<std::array<double, 3>> eye, look_at;  // default: a 3/4 view framing the rest box
  double vfov = 35;                                   // vertical field of view [degrees], in (0, 180)
  int64_t width = 1280, height = 720;                 // [pixels], in [16, 16384]
  int64_t spp = 4;                                    // samples per pixel, in [1, 1024]
  std::string material = "opaque";                    // "opaque" | "glass": every body
  double ior = 1.5;                                   // glass index of refraction, in [1, 4]
  std::string environment = "sky";                    // "sky" or a Radiance .hdr file, as written
  std::string environment_path;       // the .hdr path resolved against the scene file's folder
  int64_t every = 1;                  // render every N-th output frame (frame 0 included), >= 1
  bool damage_colors = false;         // tint damaged particles red (a debugging view)
  std::string surface = "elements";   // "elements" | "mesh": bodies drawn from the crack mesh
  int64_t smooth_cracks = 2;          // Taubin passes over the crack surfaces (surface = "mesh"), [0, 100]
  std::vector<SceneBodyLook> bodies;  // per-body looks, in the file's order
};

}  // namespace pd
