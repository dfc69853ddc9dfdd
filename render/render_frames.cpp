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
#include "trimtope_file.h"

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
                      std::vector<Vec3>* albedo, const RestTrimtopes* trimtopes,
                      const FragmentsFrame* fragments) {
  const size_t n = rest.size();
  if (frame.size() != n || frame.damage.size() != n || frame.body.size() != n)
    throw std::invalid_argument("frame " + std::to_string(frame.frame) + " has " +
                                std::to_string(frame.size()) + " particles, the rest file " +
                                std::to_string(n));
  // Which particles are trimtopes.
  std::vector<int32_t> trimtope_of(trimtopes ? n : 0, -1);
  if (trimtopes)
    for (size_t k = 0; k < trimtopes->size(); ++k) {
      const int32_t p = trimtopes->particle[k];
      if (p < 0 || size_t(p) >= n)
        throw std::invalid_argument("trimtope of particle " + std::to_string(p) + " but the rest file has " +
                                    std::to_string(n) + " particles");
      trimtope_of[size_t(p)] = int32_t(k);
    }
  // Fragment of each component id (ids are particle indices).
  std::vector<int32_t> fragment_of;
  if (fragments && frame.component.size() == n) {
    fragment_of.assign(n, -1);
    for (size_t f = 0; f < fragments->fragments.size(); ++f) {
      const int32_t id = fragments->fragments[f].id;
      if (id < 0 || size_t(id) >= n)
        throw std::invalid_argument("fragment id " + std::to_string(id) + " is not a particle index");
      fragment_of[size_t(id)] = int32_t(f);
    }
  }
  *prims = PrimitiveSet();
  albedo->clear();
  albedo->reserve(n);
  for (size_t i = 0; i < n; ++i) {
    albedo->push_back(particle_color(frame.body[i], frame.damage[i]));
    if (trimtope_of.empty() || trimtope_of[i] < 0) {
      prims->add_cube(frame.position[i], real(0.5) * std::cbrt(real(rest.volume[i])));
      continue;
    }
    // The fragment's rigid transform, else the particle's displacement.
    const int32_t c = fragment_of.empty() ? -1 : frame.component[i];
    const int32_t f = c >= 0 && size_t(c) < n ? fragment_of[size_t(c)] : -1;
    if (f >= 0) {
      const Fragment& fr = fragments->fragments[size_t(f)];
      add_placed_trimtope(prims, *trimtopes, size_t(trimtope_of[i]), fr.rotation, fr.translation);
    } else {
      const Vec3 u = frame.position[i] - rest.position[i];
      add_placed_trimtope(prims, *trimtopes, size_t(trimtope_of[i]), Eigen::Matrix3d::Identity(),
                          Eigen::Vector3d(u.x, u.y, u.z));
    }
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
  if (o.material != "opaque" && o.material != "glass")
    throw std::invalid_argument("render: material '" + o.material + "' (allowed: opaque, glass)");
  if (!(o.ior >= 1) || !(o.ior <= 4)) throw std::invalid_argument("render: ior must be in [1, 4]");
  const RestData rest = read_rest_file((fs::path(o.dir) / kRestFileName).string());
  const std::vector<std::string> frames = list_frame_files(o.dir);
  if (frames.empty()) throw io_error("read", o.dir, "no frame_*.pfr files");
  const std::string out = o.out.empty() ? (fs::path(o.dir) / "render").string() : o.out;
  ensure_directory(out);

  Camera camera;
  RenderSettings settings = run_settings(o, rest, frames, &camera);
  settings.ior = o.ior;
  // Voronoi bodies: their trimtopes, written by the run.
  std::optional<RestTrimtopes> trimtopes;
  const fs::path trimtope_path = fs::path(o.dir) / kTrimtopesFileName;
  if (fs::exists(trimtope_path)) trimtopes = read_trimtopes_file(trimtope_path.string());
  std::string note;
  const Backend backend = choose_backend(o.backend, &note);
  if (!note.empty()) std::printf("backend    %s\n", note.c_str());
  const std::unique_ptr<Renderer> renderer = make_renderer(backend == Backend::kCuda);
  std::printf("device     %s [%s]\n", renderer->device_name().c_str(), backend_name(backend));
  const size_t n_trim = trimtopes ? trimtopes->size() : 0;
  std::printf("images     %d x %d, %d spp, %zu cubes, %zu trimtopes (%s), %zu frames -> %s\n", o.width,
              o.height, o.spp, rest.size() - n_trim, n_trim, o.material.c_str(), frames.size(), out.c_str());

  double ray_seconds = 0;
  int64_t rays = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    // Scene of this frame, its kd-tree, the image.
    const FrameData frame = read_frame_file(frames[k]);
    std::optional<FragmentsFrame> fragments;
    const fs::path fragments_path = fs::path(o.dir) / fragments_file_name(frame.frame);
    if (trimtopes && fs::exists(fragments_path)) fragments = read_fragments_file(fragments_path.string());
    PrimitiveSet prims;
    std::vector<Vec3> albedo;
    frame_primitives(rest, frame, &prims, &albedo, trimtopes ? &*trimtopes : nullptr,
                     fragments ? &*fragments : nullptr);
    std::vector<uint8_t> material(o.material == "glass" ? albedo.size() : 0, kMaterialGlass);
    const RenderScene scene = make_render_scene(std::move(prims), std::move(albedo), std::move(material));
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
