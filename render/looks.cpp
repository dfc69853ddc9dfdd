#include "render/looks.h"

#include "render/geometry.h"

namespace pd {

namespace {

struct NamedLook {
  const char* name;
  BodyLook look;
};

// Linear RGB albedos of the materials they name (sRGB swatches of the materials, linearised).
const NamedLook kLooks[] = {
    {"glass", {kMaterialGlass, {real(0.80), real(0.90), real(0.92)}}},
    {"clay", {kMaterialOpaque, {real(0.48), real(0.20), real(0.10)}}},
    {"concrete", {kMaterialOpaque, {real(0.40), real(0.40), real(0.38)}}},
    {"plaster", {kMaterialOpaque, {real(0.78), real(0.76), real(0.72)}}},
    {"steel", {kMaterialOpaque, {real(0.35), real(0.36), real(0.38)}}},
    {"wood", {kMaterialOpaque, {real(0.45), real(0.28), real(0.14)}}},
};

}  // namespace

const std::vector<std::string>& look_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const NamedLook& l : kLooks) v.emplace_back(l.name);
    return v;
  }();
  return names;
}

std::optional<BodyLook> named_look(const std::string& name) {
  for (const NamedLook& l : kLooks)
    if (name == l.name) return l.look;
  return std::nullopt;
}

BodyLook default_look(int32_t body, bool glass) {
  static const Vec3 palette[] = {{real(0.62), real(0.70), real(0.78)}, {real(0.78), real(0.42), real(0.24)},
                                 {real(0.30), real(0.50), real(0.72)}, {real(0.50), real(0.66), real(0.36)},
                                 {real(0.80), real(0.68), real(0.30)}, {real(0.56), real(0.42), real(0.68)}};
  constexpr int kColors = sizeof palette / sizeof palette[0];
  return {glass ? uint8_t(kMaterialGlass) : uint8_t(kMaterialOpaque),
          palette[((body % kColors) + kColors) % kColors]};
}

Vec3 particle_color(const BodyLook& look, float damage, bool damage_colors) {
  if (!damage_colors) return look.albedo;
  const Vec3 damaged{real(0.85), real(0.12), real(0.08)};
  return lerp(look.albedo, damaged, real(0.7) * clamp01(real(damage)));
}

}  // namespace pd
