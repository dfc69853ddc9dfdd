// Backend choice and the host-side preparation shared by both renderers.
#include "render/renderer.h"

#include "render/hidden_tets.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace pd {

RenderScene make_render_scene(PrimitiveSet prims, std::vector<Vec3> albedo, std::vector<uint8_t> material,
                              const KdBuildOptions& options, HiddenElements elements) {
  if (albedo.size() != prims.kind.size())
    throw std::invalid_argument("render scene: " + std::to_string(albedo.size()) + " albedos for " +
                                std::to_string(prims.size()) + " primitives");
  if (!material.empty() && material.size() != prims.kind.size())
    throw std::invalid_argument("render scene: " + std::to_string(material.size()) + " materials for " +
                                std::to_string(prims.size()) + " primitives");
  RenderScene scene;
  const std::vector<Box> boxes = prims.bounds();
  // Union tolerance: a fraction of the median element's smallest box side.
  std::vector<real> sides(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Vec3 e = boxes[i].hi - boxes[i].lo;
    sides[i] = rmin(e.x, rmin(e.y, e.z));
  }
  if (!sides.empty()) {
    std::nth_element(sides.begin(), sides.begin() + long(sides.size() / 2), sides.end());
    scene.join_gap = kJoinGapFraction * sides[sides.size() / 2];
  }
  // The kd-tree holds the primitives a ray can reach first (hidden_tets.h); its primitive
  // indices are those of the whole set, so albedo and material stay per primitive.
  const std::vector<uint8_t> hidden =
      elements == HiddenElements::kCull ? find_hidden_tets(prims, material) : std::vector<uint8_t>();
  scene.hidden = std::count(hidden.begin(), hidden.end(), uint8_t(1));
  scene.tree = build_kdtree_without(boxes, hidden, options);
  scene.prims = std::move(prims);
  scene.albedo = std::move(albedo);
  scene.material = std::move(material);
  return scene;
}

ShadingParams make_shading_params(const RenderSettings& s) {
  ShadingParams p;
  p.sky = s.sky;
  p.sun = normalize(s.sky.sun_direction);
  p.sky_sh = s.environment ? s.environment->sh : sky_sh9(s.sky);
  p.specular = s.environment ? real(0) : s.specular;  // the highlight is the sky's sun
  p.shininess = s.shininess;
  p.floor = s.floor ? 1 : 0;
  p.floor_y = s.floor_y;
  p.plank_width = s.plank_width;
  p.fade_distance = s.fade_distance;
  return p;
}

std::unique_ptr<Renderer> make_renderer(bool gpu) {
  if (!gpu) return make_cpu_renderer();
#if defined(PERIFRAC_HAS_CUDA)
  return make_cuda_renderer();
#else
  throw std::runtime_error("CUDA renderer unavailable: this build has no CUDA support");
#endif
}

}  // namespace pd
