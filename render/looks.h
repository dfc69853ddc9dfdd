// How a body looks in renders: a named look (a surface and a colour) chosen per body in the
// scene's [render] block (docs/scene-reference.md), and the colour of one particle of it.
// Damage tints particles red only when asked for (a debugging view, not the animation's look).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cuda/vec3.h"
#include "render/shading.h"

namespace pd {

struct BodyLook {
  uint8_t surface = kMaterialOpaque;  // SurfaceMaterial
  Vec3 albedo{0, 0, 0};               // linear RGB of an opaque surface (glass is clear)
};

// The looks a scene may name, in the order the documentation lists them.
const std::vector<std::string>& look_names();
// "glass", "clay", "concrete", "plaster", "steel", "wood"; nullopt for any other name.
std::optional<BodyLook> named_look(const std::string& name);
// The look of a body with no look of its own: a colour of a fixed palette by its index (any
// integer), opaque or glass as the run's `material` says.
BodyLook default_look(int32_t body, bool glass);

// Linear RGB albedo of a particle of the given look; with `damage_colors`, tinted towards red
// with its damage in [0, 1].
Vec3 particle_color(const BodyLook& look, float damage, bool damage_colors);

// The looks of a run's bodies: a look per body id where the scene gives one, the default look
// for the others (glass for all with `glass`), damage colours on request.
struct RunLooks {
  std::vector<std::optional<BodyLook>> bodies;  // index: body id
  bool glass = false;
  bool damage_colors = false;

  BodyLook of(int32_t body) const {
    if (body >= 0 && size_t(body) < bodies.size() && bodies[size_t(body)]) return *bodies[size_t(body)];
    return default_look(body, glass);
  }
};

}  // namespace pd
