// Backend choice and the host-side preparation shared by both renderers.
#include "render/renderer.h"

#include "render/hidden_tets.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace pd {

namespace {

// The union tolerance: kJoinGapFraction of the median element's smallest box side. Triangles
// (flat boxes) count only where there is no element, then by their longest box side.
real join_gap_of(const PrimitiveSet& prims, const std::vector<Box>& boxes) {
  std::vector<real> elements, triangles;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Vec3 e = boxes[i].hi - boxes[i].lo;
    if (prims.kind[i] == kPrimTriangle)
      triangles.push_back(rmax(e.x, rmax(e.y, e.z)));
    else
      elements.push_back(rmin(e.x, rmin(e.y, e.z)));
  }
  std::vector<real>& sides = elements.empty() ? triangles : elements;
  if (sides.empty()) return 0;
  std::nth_element(sides.begin(), sides.begin() + long(sides.size() / 2), sides.end());
  return kJoinGapFraction * sides[sides.size() / 2];
}

}  // namespace

RenderScene make_render_scene(PrimitiveSet prims, std::vector<Vec3> albedo, std::vector<uint8_t> material,
                              const KdBuildOptions& options, HiddenElements elements,
                              const std::vector<uint8_t>& left_out) {
  if (albedo.size() != prims.kind.size())
    throw std::invalid_argument("render scene: " + std::to_string(albedo.size()) + " albedos for " +
                                std::to_string(prims.size()) + " primitives");
  if (!material.empty() && material.size() != prims.kind.size())
    throw std::invalid_argument("render scene: " + std::to_string(material.size()) + " materials for " +
                                std::to_string(prims.size()) + " primitives");
  if (!left_out.empty() && left_out.size() != prims.kind.size())
    throw std::invalid_argument("render scene: " + std::to_string(left_out.size()) + " left-out flags for " +
                                std::to_string(prims.size()) + " primitives");
  RenderScene scene;
  const std::vector<Box> boxes = prims.bounds();
  scene.join_gap = join_gap_of(prims, boxes);
  // The kd-tree holds the primitives a ray can reach first (hidden_tets.h) that are not left out;
  // its primitive indices are those of the whole set, so albedo and material stay per primitive.
  // Left-out tetrahedra cover no face of their neighbours: they count as glass there.
  std::vector<uint8_t> hidden;
  if (elements == HiddenElements::kCull) {
    std::vector<uint8_t> surfaces = material;
    if (!left_out.empty()) {
      surfaces.resize(prims.kind.size(), kMaterialOpaque);
      for (size_t i = 0; i < left_out.size(); ++i)
        if (left_out[i]) surfaces[i] = kMaterialGlass;
    }
    hidden = find_hidden_tets(prims, surfaces);
  }
  scene.hidden = std::count(hidden.begin(), hidden.end(), uint8_t(1));
  if (!left_out.empty()) {
    hidden.resize(left_out.size(), 0);
    for (size_t i = 0; i < left_out.size(); ++i) hidden[i] |= left_out[i];
  }
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
