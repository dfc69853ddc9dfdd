// The raytracer seen from the host: one interface, a CPU (OpenMP) and a CUDA backend running the
// same per-pixel kernel (renderer_impl.h). A scene is a set of primitives with one albedo each
// and a kd-tree built over them on the host; render_frame uploads it, traces one primary ray per
// sample and returns the 8-bit sRGB image.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cuda/views.h"
#include "render/camera.h"
#include "render/environment.h"
#include "render/image.h"
#include "render/kdtree.h"
#include "render/primitive_set.h"
#include "render/shading.h"

namespace pd {

struct RenderScene {
  PrimitiveSet prims;
  std::vector<Vec3> albedo;       // linear RGB, one per primitive
  std::vector<uint8_t> material;  // SurfaceMaterial per primitive; empty: all opaque
  real join_gap =
      0;        // elements closer than this touch (union_walk.h): kJoinGapFraction of the median element
  KdTree tree;  // over the primitives that are neither hidden nor left out
  int64_t hidden = 0;                 // tetrahedra left out of the tree (hidden_tets.h)
  std::vector<Collider> colliders;    // drawn at their pose, planes excepted (collider_hit.h)
  std::vector<float> collider_grids;  // the mesh colliders' distance grids (Collider::grid_offset)
  Vec3 collider_albedo{real(0.35), real(0.36), real(0.38)};  // linear RGB: dark steel
};

// kCull leaves the tetrahedra that no ray from outside can reach first out of the kd-tree
// (hidden_tets.h): the same image, a smaller tree. kKeep puts every primitive in (benchmarks).
enum class HiddenElements { kCull, kKeep };

// The union tolerance as a fraction of the median element's smallest box side.
constexpr real kJoinGapFraction = real(0.005);

// Builds the kd-tree and the union tolerance (from the elements; from the triangles only where
// there are no elements); throws std::invalid_argument unless there is one albedo per primitive,
// no material or one per primitive, and no `left_out` or one flag per primitive. Primitives whose
// `left_out` flag is 1 stay in the set (indices unchanged) but not in the kd-tree: no ray meets
// them (elements drawn by a surface mesh instead).
RenderScene make_render_scene(PrimitiveSet prims, std::vector<Vec3> albedo,
                              std::vector<uint8_t> material = {}, const KdBuildOptions& options = {},
                              HiddenElements elements = HiddenElements::kCull,
                              const std::vector<uint8_t>& left_out = {});

struct RenderSettings {
  int width = 1280, height = 720;
  int spp = 1;  // samples (primary rays) per pixel, fixed stratified pattern (camera.h)
  Sky sky;
  // An .hdr environment in place of the sky (light and background; no sun highlight); null: the
  // sky.
  std::shared_ptr<const EnvironmentMap> environment;
  real specular = real(0.04), shininess = 60;  // Blinn-Phong
  bool floor = true;
  real floor_y = 0;
  real plank_width = real(0.1);    // wood texture scale [m]
  real fade_distance = real(100);  // floor fade into the horizon [m]
  real exposure = real(0.85);      // linear scale before the sRGB encoding
  real ior = real(1.5);            // index of refraction of glass elements
  bool count_rays = false;         // count every traced ray (RenderResult::traced_rays)
  // Asked between parts of a big frame (up to 64) when set: true leaves the frame unfinished
  // (RenderResult::stopped), so that a long frame can be interrupted.
  std::function<bool()> stop;
};

// The kernel's shading parameters for `s` (projects the sky to SH).
ShadingParams make_shading_params(const RenderSettings& s);

struct RenderResult {
  ImageRGB8 image;
  double seconds = 0;  // kernel time (upload and download excluded)
  int64_t rays = 0;    // primary rays traced
  // With RenderSettings::count_rays: all nearest-hit rays (primary, Fresnel reflections, rays
  // leaving glass collections); the steps of the walk inside glass are not rays here.
  int64_t traced_rays = 0;
  bool stopped = false;  // RenderSettings::stop said so: the image is unfinished
};

class Renderer {
 public:
  virtual ~Renderer() = default;
  virtual std::string device_name() const = 0;
  // Throws std::invalid_argument for bad settings (image size, spp, camera).
  virtual RenderResult render_frame(const RenderScene& scene, const Camera& camera,
                                    const RenderSettings& settings) = 0;
};

// gpu = false: the CPU renderer. gpu = true: the CUDA renderer; throws std::runtime_error when
// CUDA is not compiled in or no device is usable.
std::unique_ptr<Renderer> make_renderer(bool gpu);
// The backends behind make_renderer; make_cuda_renderer exists in CUDA builds only.
std::unique_ptr<Renderer> make_cpu_renderer();
std::unique_ptr<Renderer> make_cuda_renderer();

}  // namespace pd
