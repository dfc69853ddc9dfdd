#include "render_frames.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "../host/app/backend_choice.h"
#include "../host/app/run.h"
#include "../host/io/atomic_file.h"
#include "../host/io/frame_file.h"

namespace pd {

namespace fs = std::filesystem;

std::vector<std::string> list_frame_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("frame_", 0) == 0 && it->path().extension() == ".pfr" && it->is_regular_file())
      files.push_back(it->path().string());
  }
  if (ec) throw io_error_errno("list", dir, ec.value());
  std::sort(files.begin(), files.end());
  return files;
}

Vec3 particle_color(int32_t body, float damage) {
  static const Vec3 palette[] = {{real(0.62), real(0.70), real(0.78)}, {real(0.78), real(0.42), real(0.24)},
                                 {real(0.30), real(0.50), real(0.72)}, {real(0.50), real(0.66), real(0.36)},
                                 {real(0.80), real(0.68), real(0.30)}, {real(0.56), real(0.42), real(0.68)}};
  constexpr int kColors = sizeof palette / sizeof palette[0];
  const Vec3 base = palette[((body % kColors) + kColors) % kColors];
  const Vec3 damaged{real(0.85), real(0.12), real(0.08)};
  return lerp(base, damaged, real(0.7) * clamp01(real(damage)));
}

void frame_primitives(const RestData& rest, const FrameData& frame, PrimitiveSet* prims,
                      std::vector<Vec3>* albedo) {
  if (frame.size() != rest.size() || frame.damage.size() != rest.size() || frame.body.size() != rest.size())
    throw std::invalid_argument("frame " + std::to_string(frame.frame) + " has " +
                                std::to_string(frame.size()) + " particles, the rest file " +
                                std::to_string(rest.size()));
  *prims = PrimitiveSet();
  albedo->clear();
  albedo->reserve(rest.size());
  for (size_t i = 0; i < rest.size(); ++i) {
    prims->add_cube(frame.position[i], real(0.5) * std::cbrt(real(rest.volume[i])));
    albedo->push_back(particle_color(frame.body[i], frame.damage[i]));
  }
}

Box cube_bounds(const std::vector<Vec3>& positions, const std::vector<float>& volume) {
  Box b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (size_t i = 0; i < positions.size(); ++i) {
    const real h = real(0.5) * std::cbrt(real(volume[i]));
    b.lo = vmin(b.lo, positions[i] - Vec3{h, h, h});
    b.hi = vmax(b.hi, positions[i] + Vec3{h, h, h});
  }
  return b;
}

namespace {

// Camera, floor and texture scale for the whole run, from the rest configuration (and the last
// frame for the floor, where fallen pieces lie).
RenderSettings run_settings(const RenderOptions& o, const RestData& rest,
                            const std::vector<std::string>& frames, Camera* camera) {
  RenderSettings s;
  s.width = o.width;
  s.height = o.height;
  s.spp = o.spp;
  s.floor = o.floor;
  const Box box = cube_bounds(rest.position, rest.volume);
  const real size = length(box.hi - box.lo);
  *camera = frame_box(box, o.width, o.height, o.vfov_degrees);
  if (o.eye) camera->eye = *o.eye;
  if (o.look_at) camera->look_at = *o.look_at;
  s.plank_width = size / 5;
  s.fade_distance = 20 * size;
  if (o.floor_y) {
    s.floor_y = *o.floor_y;
  } else {
    s.floor_y = box.lo.y;
    if (!frames.empty())
      s.floor_y = rmin(s.floor_y, cube_bounds(read_frame_file(frames.back()).position, rest.volume).lo.y);
  }
  return s;
}

}  // namespace

int render_frames(const RenderOptions& o) {
  if (o.width <= 0 || o.height <= 0) throw std::invalid_argument("render: image size must be positive");
  if (o.spp < 1) throw std::invalid_argument("render: --spp must be at least 1");
  const RestData rest = read_rest_file((fs::path(o.dir) / kRestFileName).string());
  const std::vector<std::string> frames = list_frame_files(o.dir);
  if (frames.empty()) throw io_error("read", o.dir, "no frame_*.pfr files");
  const std::string out = o.out.empty() ? (fs::path(o.dir) / "render").string() : o.out;
  ensure_directory(out);

  Camera camera;
  const RenderSettings settings = run_settings(o, rest, frames, &camera);
  std::string note;
  const Backend backend = choose_backend(o.backend, &note);
  if (!note.empty()) std::printf("backend    %s\n", note.c_str());
  const std::unique_ptr<Renderer> renderer = make_renderer(backend == Backend::kCuda);
  std::printf("device     %s [%s]\n", renderer->device_name().c_str(), backend_name(backend));
  std::printf("images     %d x %d, %d spp, %zu cubes, %zu frames -> %s\n", o.width, o.height, o.spp,
              rest.size(), frames.size(), out.c_str());

  double ray_seconds = 0;
  int64_t rays = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    // Scene of this frame, its kd-tree, the image.
    const FrameData frame = read_frame_file(frames[k]);
    PrimitiveSet prims;
    std::vector<Vec3> albedo;
    frame_primitives(rest, frame, &prims, &albedo);
    const RenderScene scene = make_render_scene(std::move(prims), std::move(albedo));
    const RenderResult r = renderer->render_frame(scene, camera, settings);
    const std::string png =
        (fs::path(out) / fs::path(frames[k]).filename().replace_extension(".png")).string();
    write_png(png, r.image);
    ray_seconds += r.seconds;
    rays += r.rays;
    const KdTreeStats& t = scene.tree.stats;
    std::printf("frame %zu/%zu  kd-tree %.2f s (%lld nodes, depth %d)  render %.3f s  %.2f Mrays/s  %s\n",
                k + 1, frames.size(), t.build_seconds, (long long)t.nodes, t.depth, r.seconds,
                1e-6 * double(r.rays) / r.seconds, png.c_str());
    std::fflush(stdout);
  }
  std::printf("rendered   %zu frames, %.2f Mrays/s overall\n", frames.size(),
              1e-6 * double(rays) / ray_seconds);
  return kExitOk;
}

}  // namespace pd
