#include "host/app/render_frames.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "host/app/backend_choice.h"
#include "host/app/checkpoint.h"
#include "host/app/run.h"
#include "host/app/run_folder.h"
#include "host/fragments/crack_mesh_file.h"
#include "host/fragments/tet_file.h"
#include "host/fragments/trimtope_file.h"
#include "host/geometry/collider_mesh.h"
#include "host/geometry/distance_grid.h"
#include "host/geometry/mesh_check.h"
#include "host/io/atomic_file.h"
#include "host/io/collider_file.h"
#include "host/io/frame_file.h"
#include "host/io/input_file.h"
#include "host/io/interrupt.h"
#include "host/io/png_file.h"
#include "render/movie.h"

namespace pd {

namespace fs = std::filesystem;

std::vector<std::string> select_frame_files(const std::string& dir, const RunContents& run,
                                            const std::vector<int64_t>& wanted, std::string* note) {
  std::vector<int64_t> partial;
  const std::map<int64_t, std::string> complete = complete_frame_files(dir, run, &partial);
  if (!partial.empty()) {
    std::string numbers;
    for (int64_t f : partial) numbers += (numbers.empty() ? "" : ", ") + std::to_string(f);
    *note = "frame " + numbers +
            " left out: its files are incomplete (the run stopped while writing it, or " + "is writing it)";
  }
  std::vector<std::string> chosen;
  if (wanted.empty()) {
    for (const auto& [frame, file] : complete) chosen.push_back(file);
    return chosen;
  }
  std::vector<int64_t> frames = wanted;  // (in order, each once)
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  for (int64_t f : frames) {
    const auto it = complete.find(f);
    if (it == complete.end())
      throw std::invalid_argument(
          "render: --frames " + std::to_string(f) + ": no such frame in '" + dir + "' (allowed: " +
          (complete.empty() ? std::string("none, the folder has no complete frame_*.pfr file")
                            : std::to_string(complete.begin()->first) + " to " +
                                  std::to_string(complete.rbegin()->first)) +
          ")");
    chosen.push_back(it->second);
  }
  return chosen;
}

RenderOptions render_options_from_scene(const Scene& scene, const std::string& dir) {
  const SceneRender& r = *scene.render;
  RenderOptions o;
  o.dir = dir;
  o.width = int(r.width);
  o.height = int(r.height);
  o.spp = int(r.spp);
  if (r.eye) o.eye = Vec3{real((*r.eye)[0]), real((*r.eye)[1]), real((*r.eye)[2])};
  if (r.look_at) o.look_at = Vec3{real((*r.look_at)[0]), real((*r.look_at)[1]), real((*r.look_at)[2])};
  o.vfov_degrees = real(r.vfov);
  if (scene.floor) o.floor_y = real(scene.floor_height);
  o.material = r.material;
  o.ior = real(r.ior);
  o.environment = r.environment == "sky" ? "sky" : r.environment_path;
  o.damage_colors = r.damage_colors;
  o.surface = r.surface;
  o.smooth_cracks = int(r.smooth_cracks);
  // Body looks by body id (the body's index in the scene).
  o.body_looks.resize(scene.bodies.size());
  for (const SceneBodyLook& l : r.bodies)
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      if (scene.bodies[b].name != l.body) continue;
      BodyLook look = l.look.empty() ? default_look(int32_t(b), r.material == "glass") : *named_look(l.look);
      if (l.color) look.albedo = Vec3{real((*l.color)[0]), real((*l.color)[1]), real((*l.color)[2])};
      o.body_looks[b] = look;
    }
  return o;
}

void check_render_options(const RenderOptions& o) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("render: " + what); };
  if (o.width <= 0 || o.height <= 0) bad("image size must be positive");
  if (o.spp < 1) bad("--spp must be at least 1");
  if (!(o.vfov_degrees > 0 && o.vfov_degrees < 180))
    bad("vfov " + std::to_string(o.vfov_degrees) + " (allowed: degrees in (0, 180))");
  if (o.material != "opaque" && o.material != "glass")
    bad("material '" + o.material + "' (allowed: opaque, glass)");
  if (!(o.ior >= 1) || !(o.ior <= 4)) {
    char ior[48];
    std::snprintf(ior, sizeof ior, "ior %g (allowed: 1 to 4)", double(o.ior));
    bad(ior);
  }
  // (A camera farther out would overflow the float vectors of its view.)
  constexpr real kFarthest = real(1e9);
  for (const auto& [name, point] : {std::pair{"eye", o.eye}, std::pair{"look-at", o.look_at}})
    if (point && !(std::fabs(point->x) <= kFarthest && std::fabs(point->y) <= kFarthest &&
                   std::fabs(point->z) <= kFarthest)) {
      char where[96];
      std::snprintf(where, sizeof where, "%s %g,%g,%g", name, double(point->x), double(point->y),
                    double(point->z));
      bad(std::string(where) + " is too far out (allowed: coordinates within 1e9 m)");
    }
  if (o.surface != "elements" && o.surface != "mesh")
    bad("surface '" + o.surface + "' (allowed: elements, mesh)");
  if (o.smooth_cracks < 0 || o.smooth_cracks > 100) bad("--smooth-cracks must be in [0, 100]");
  if (o.environment.empty()) bad("environment is empty (allowed: sky, or the path of a Radiance .hdr file)");
  // A file that is there must be a bounded one (a missing one is the loader's to report).
  std::string why;
  std::error_code ec;
  if (o.environment != "sky" && fs::exists(o.environment, ec) && !is_bounded_input(o.environment, why))
    bad("--environment '" + o.environment + "': " + why + " (allowed: sky, or a Radiance .hdr file)");
}

RunRenderer::RunRenderer(const RenderOptions& o, const std::string& last_frame) : options_(o) {
  check_render_options(o);
  if (o.check_run_files) run_ = read_run_contents(o.dir);
  rest_ = read_rest_file((fs::path(o.dir) / kRestFileName).string());
  out_ = o.out.empty() ? (fs::path(o.dir) / "render").string() : o.out;
  // Rest-space geometry the run wrote: Voronoi bodies' trimtopes, tet bodies' tetrahedra.
  if (const auto trimtope_path = run_file(kTrimtopesFileName))
    trimtopes_ = read_trimtopes_file(*trimtope_path);
  if (const auto tets_path = run_file(kTetsFileName)) tets_ = read_tets_file(*tets_path);

  // Camera, floor and texture scale for the whole run, from the rest configuration (and the
  // last frame for the floor, where fallen pieces lie).
  const Box box = cube_bounds(rest_.position, rest_.volume);
  const real size = length(box.hi - box.lo);
  camera_ = frame_box(box, o.width, o.height, o.vfov_degrees);
  if (o.eye) camera_.eye = *o.eye;
  if (o.look_at) camera_.look_at = *o.look_at;
  camera_frame(camera_, o.width, o.height);  // a degenerate camera fails here, before any frame
  settings_.width = o.width;
  settings_.height = o.height;
  settings_.spp = o.spp;
  settings_.floor = o.floor;
  settings_.ior = o.ior;
  settings_.plank_width = size / 5;
  settings_.fade_distance = 20 * size;
  settings_.floor_y = box.lo.y;
  if (o.floor_y)
    settings_.floor_y = *o.floor_y;
  else if (!last_frame.empty())
    settings_.floor_y =
        rmin(settings_.floor_y, cube_bounds(read_frame_file(last_frame).position, rest_.volume).lo.y);
  if (o.environment != "sky")
    settings_.environment = std::make_shared<EnvironmentMap>(load_environment(o.environment));
  settings_.stop = [] { return InterruptGuard::signal_received() != 0; };  // (a long frame stops too)

  const Backend backend = choose_backend(o.backend, &backend_note_);
  renderer_ = make_renderer(backend == Backend::kCuda);
  backend_name_ = backend_name(backend);
  ensure_directory(out_);
  remove_stale_temporaries(out_);  // (images a killed render left half-written)
}

std::optional<std::string> RunRenderer::run_file(const std::string& relative) const {
  const fs::path path = fs::path(options_.dir) / relative;
  std::error_code ec;
  if (fs::exists(path, ec)) return path.string();
  if (run_.wrote(relative))
    throw io_error("read", path.string(), "missing, though the run wrote it (run.files lists it)");
  return std::nullopt;
}

RunRenderer::~RunRenderer() = default;

std::string RunRenderer::device() const {
  return renderer_->device_name() + " [" + backend_name_ + "]";
}

std::string RunRenderer::scene_summary() const {
  const size_t n_trim = trimtopes_ ? trimtopes_->size() : 0, n_tets = tets_ ? tets_->tets.size() : 0;
  // The material of bodies without a look of their own, then what the looks per body are.
  std::string looks = options_.material;
  int glass = 0, opaque = 0;
  for (const std::optional<BodyLook>& l : options_.body_looks)
    if (l) ++(l->surface == kMaterialGlass ? glass : opaque);
  if (glass + opaque > 0)
    looks += ", looks per body: " + std::to_string(glass) + " glass, " + std::to_string(opaque) + " opaque";
  if (options_.damage_colors) looks += ", damage colours";
  if (options_.surface == "mesh")
    looks += ", crack mesh surfaces (" + std::to_string(options_.smooth_cracks) + " smoothing passes)";
  char buf[320];
  std::snprintf(buf, sizeof buf, "%zu cubes, %zu tetrahedra, %zu trimtopes (%s), %s",
                rest_.size() - n_trim - n_tets, n_tets, n_trim, looks.c_str(),
                settings_.environment ? settings_.environment->path.c_str() : "procedural sky");
  return buf;
}

FrameRenderReport RunRenderer::render(const std::string& frame_file) {
  // Scene of this frame, its kd-tree, the image.
  const FrameData frame = read_frame_file(frame_file);
  std::optional<FragmentsFrame> fragments;
  if (const auto fragments_path = run_file(fragments_file_name(frame.frame)))
    fragments = read_fragments_file(*fragments_path);
  PrimitiveSet prims;
  std::vector<Vec3> albedo;
  const RunLooks looks{options_.body_looks, options_.material == "glass", options_.damage_colors};
  frame_primitives(rest_, frame, &prims, &albedo, trimtopes_ ? &*trimtopes_ : nullptr,
                   fragments ? &*fragments : nullptr, tets_ ? &*tets_ : nullptr, looks);
  // A surface per particle, then per crack mesh triangle, where any is glass (none: all opaque).
  std::vector<uint8_t> material(albedo.size());
  for (size_t i = 0; i < material.size(); ++i) material[i] = looks.of(frame.body[i]).surface;
  std::vector<uint8_t> left_out;
  int64_t triangles = 0;
  if (options_.surface == "mesh")
    triangles = add_crack_mesh(frame.frame, frame.body, &prims, &albedo, &material, &left_out);
  if (std::find(material.begin(), material.end(), uint8_t(kMaterialGlass)) == material.end())
    material.clear();
  RenderScene scene = make_render_scene(std::move(prims), std::move(albedo), std::move(material), {},
                                        HiddenElements::kCull, left_out);
  if (const auto colliders_path = run_file(colliders_file_name(frame.frame))) {
    for (const ColliderState& c : read_colliders_file(*colliders_path)) scene.colliders.push_back(c.collider);
    add_mesh_grids(scene.colliders);
    scene.collider_grids = collider_grids_;
  }
  const RenderResult r = renderer_->render_frame(scene, camera_, settings_);
  if (r.stopped) throw Interrupted("interrupted while rendering frame " + std::to_string(frame.frame));
  FrameRenderReport report;
  report.png = (fs::path(out_) / fs::path(frame_file).filename().replace_extension(".png")).string();
  write_png(report.png, r.image);
  report.tree = scene.tree.stats;
  report.hidden = scene.hidden;
  report.triangles = triangles;
  report.render_seconds = r.seconds;
  report.rays = r.rays;
  return report;
}

int64_t RunRenderer::add_crack_mesh(int64_t frame, const std::vector<int32_t>& body, PrimitiveSet* prims,
                                    std::vector<Vec3>* albedo, std::vector<uint8_t>* material,
                                    std::vector<uint8_t>* left_out) const {
  const std::string name = crack_mesh_file_name(frame, "ply");
  const std::optional<std::string> found = run_file(name);  // (gone though the run wrote it: IoError)
  const std::string path = (fs::path(options_.dir) / name).string();
  if (!found)
    throw std::invalid_argument("render --surface mesh: no " + path +
                                " (the run must write crack meshes: fragment output on, the default)");
  CrackSurface mesh;
  try {
    mesh = read_crack_mesh(path);
  } catch (const MeshError& e) {  // (a file the run wrote, damaged: not the user's mistake)
    throw IoError(e.what());
  }
  try {
    *left_out = covered_particles(mesh, body);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("render --surface mesh: " + path + ": " + e.what());
  }
  smooth_cracks(mesh, options_.smooth_cracks);
  add_surface_triangles(mesh, corner_normals(mesh), prims, albedo, material);
  left_out->resize(size_t(prims->size()), 0);
  return int64_t(mesh.triangles.size());
}

void RunRenderer::add_mesh_grids(std::vector<Collider>& colliders) {
  if (mesh_grid_.size() < colliders.size()) mesh_grid_.resize(colliders.size());
  for (size_t k = 0; k < colliders.size(); ++k) {
    if (colliders[k].shape != kColliderMesh) continue;
    if (mesh_grid_[k].shape != kColliderMesh) {  // first seen: its grid from colliders.obj
      if (collider_shapes_.empty()) collider_shapes_ = read_collider_obj(options_.dir + "/colliders.obj");
      if (k >= collider_shapes_.size() || collider_shapes_[k].triangles.empty())
        throw MeshError(options_.dir + "/colliders.obj", "no surface for mesh collider " + std::to_string(k));
      TriMesh mesh = collider_shapes_[k];
      bool closed = true;
      try {
        check_solid(mesh, options_.dir + "/colliders.obj", {});
      } catch (const MeshError&) {
        closed = false;  // an open sheet: drawn from its unsigned distance
      }
      const Vec3d extent = bounds(mesh).size();
      const double cell = std::max({extent[0], extent[1], extent[2]}) / 128;
      const DistanceGrid g = distance_grid(mesh, closed, cell, 2 * cell);
      Collider& c = mesh_grid_[k];
      c.shape = kColliderMesh;
      c.grid_origin = {real(g.origin[0]), real(g.origin[1]), real(g.origin[2])};
      c.grid_cell = real(g.cell);
      for (int a = 0; a < 3; ++a) c.grid_dims[a] = g.dims[size_t(a)];
      c.grid_offset = int64_t(collider_grids_.size());
      collider_grids_.insert(collider_grids_.end(), g.distance.begin(), g.distance.end());
    }
    const Collider& g = mesh_grid_[k];
    colliders[k].grid_origin = g.grid_origin;
    colliders[k].grid_cell = g.grid_cell;
    for (int a = 0; a < 3; ++a) colliders[k].grid_dims[a] = g.grid_dims[a];
    colliders[k].grid_offset = g.grid_offset;
  }
}

namespace {

// The frame number of a frame file's name, frame_NNNNN.pfr.
int64_t frame_number(const std::string& frame_file) {
  const std::string stem = fs::path(frame_file).stem().string();
  return std::strtoll(stem.c_str() + stem.find('_') + 1, nullptr, 10);
}

}  // namespace

namespace {

bool given(const RenderOptions& o, const char* option) {
  return std::find(o.given.begin(), o.given.end(), option) != o.given.end();
}

// `cli` with the run's scene's [render] settings for every option not given on the command
// line, where the run's manifest names a scene that still loads unchanged (same fingerprint) and
// has a [render] block; else `cli` as it is. `note`: what was taken, or why nothing was.
RenderOptions with_scene_render(const RenderOptions& cli, std::string* note) {
  std::optional<RunManifest> manifest;
  try {
    manifest = read_manifest(cli.dir);
  } catch (const RunFolderError&) {
  }
  if (!manifest) return cli;
  std::error_code ec;
  if (!fs::is_regular_file(manifest->scene_path, ec) ||
      scene_fingerprint(manifest->scene_path, manifest->overrides) != manifest->scene_hash) {
    *note = "the run's scene " + manifest->scene_path + " is gone or changed: its [render] block is not used";
    return cli;
  }
  Scene scene;
  try {
    scene = load_scene(manifest->scene_path, manifest->overrides);
  } catch (const std::exception& e) {
    *note = std::string("the run's scene does not load (") + e.what() + "): its [render] block is not used";
    return cli;
  }
  if (!scene.render) return cli;
  RenderOptions o = render_options_from_scene(scene, cli.dir);
  o.out = cli.out;
  o.backend = cli.backend;
  o.movie = cli.movie;
  o.frames = cli.frames;
  o.given = cli.given;
  if (given(cli, "--width")) o.width = cli.width;
  if (given(cli, "--height")) o.height = cli.height;
  if (given(cli, "--spp")) o.spp = cli.spp;
  if (given(cli, "--eye")) o.eye = cli.eye;
  if (given(cli, "--look-at")) o.look_at = cli.look_at;
  if (given(cli, "--vfov")) o.vfov_degrees = cli.vfov_degrees;
  if (given(cli, "--material")) {
    o.material = cli.material;
    o.body_looks.clear();  // one material for every body, as the option says
  }
  if (given(cli, "--ior")) o.ior = cli.ior;
  if (given(cli, "--environment")) o.environment = cli.environment;
  if (given(cli, "--damage-colors")) o.damage_colors = cli.damage_colors;
  if (given(cli, "--surface")) o.surface = cli.surface;
  if (given(cli, "--smooth-cracks")) o.smooth_cracks = cli.smooth_cracks;
  *note = "the scene's [render] block (" + scene.path + "), with the options given here";
  return o;
}

}  // namespace

int render_frames(const RenderOptions& cli) {
  std::string scene_note;
  const RenderOptions o = with_scene_render(cli, &scene_note);
  check_render_options(o);
  // A folder that is not a run's is the user's mistake (exit 2), not a failure to read one.
  std::error_code ec;
  if (!fs::is_directory(o.dir, ec))
    throw std::invalid_argument("render: '" + o.dir + "' is " +
                                (fs::exists(o.dir, ec) ? "not a folder" : "not there") +
                                " (allowed: the output folder of `perifrac run`, its --out)");
  if (!o.out.empty() && fs::exists(o.out, ec) && !fs::is_directory(o.out, ec))
    throw std::invalid_argument("render: --out '" + o.out +
                                "' is a file, not a folder (allowed: a folder, new or holding images)");
  const RunContents run = read_run_contents(o.dir);
  std::string frames_note;
  const std::vector<std::string> frames = select_frame_files(o.dir, run, o.frames, &frames_note);
  if (frames.empty()) {  // (--frames names frames that are there: select_frame_files)
    if (run.frames_written && *run.frames_written >= 0 && !run.wrote(frame_file_name(0, "pfr")))
      throw std::invalid_argument("render: the run in '" + o.dir +
                                  "' wrote no .pfr frames (output.binary = false), which render reads "
                                  "(allowed: a run with output.binary = true, the default)");
    throw std::invalid_argument(
        "render: '" + o.dir + "' holds no complete frame_*.pfr" +
        (fs::exists(fs::path(o.dir) / kRestFileName, ec) ? "" : " nor " + std::string(kRestFileName)) +
        " (allowed: the output folder of `perifrac run`, its --out, once frame 0 is written)");
  }
  RunRenderer renderer(o, frames.back());
  if (!renderer.backend_note().empty()) std::printf("backend    %s\n", renderer.backend_note().c_str());
  std::printf("device     %s\n", renderer.device().c_str());
  if (!scene_note.empty()) std::printf("settings   %s\n", scene_note.c_str());
  if (!frames_note.empty()) std::printf("frames     %s\n", frames_note.c_str());
  std::printf("images     %d x %d, %d spp, %s, %zu frames -> %s\n", o.width, o.height, o.spp,
              renderer.scene_summary().c_str(), frames.size(), renderer.image_dir().c_str());
  // Images written into a run's folder join its journal (host/app/run_folder.h): --overwrite and
  // resume remove them with the frames they show.
  std::optional<OutputJournal> journal;
  if (fs::exists(fs::path(o.dir) / kManifestFileName)) journal.emplace(o.dir);
  double ray_seconds = 0;
  int64_t rays = 0;
  std::vector<std::string> images;
  const InterruptGuard interrupt;  // SIGINT/SIGTERM: stop between two frames, their images complete
  for (size_t k = 0; k < frames.size(); ++k) {
    if (InterruptGuard::signal_received()) {
      std::printf("interrupted after %zu of %zu frames: their images are complete\n", k, frames.size());
      return kExitInterrupted;
    }
    if (journal) journal->set_frame(frame_number(frames[k]));
    FrameRenderReport r;
    try {
      r = renderer.render(frames[k]);
    } catch (const Interrupted& e) {
      std::printf("%s: the %zu images before it are complete\n", e.what(), k);
      return kExitInterrupted;
    }
    images.push_back(r.png);
    ray_seconds += r.render_seconds;
    rays += r.rays;
    const std::string mesh =
        o.surface == "mesh" ? ", " + std::to_string(r.triangles) + " mesh triangles" : "";
    std::printf(
        "frame %zu/%zu  kd-tree %.2f s (%lld nodes, depth %d, %lld hidden%s)  render %.3f s  %.2f Mrays/s  "
        "%s\n",
        k + 1, frames.size(), r.tree.build_seconds, (long long)r.tree.nodes, r.tree.depth,
        (long long)r.hidden, mesh.c_str(), r.render_seconds, 1e-6 * double(r.rays) / r.render_seconds,
        r.png.c_str());
    std::fflush(stdout);
  }
  std::printf("rendered   %zu frames, %.2f Mrays/s overall\n", frames.size(),
              1e-6 * double(rays) / ray_seconds);
  // The movie of every frame, from this render's images (not others the folder may hold).
  const std::string movie = renderer.image_dir() + "/" + kMovieFileName;
  MovieResult made;
  if (o.movie && o.frames.empty()) {
    announce_output(movie);
    made = make_movie(images, movie);
    std::printf("movie      %s\n", made.message.c_str());
    if (InterruptGuard::signal_received()) return kExitInterrupted;  // (ffmpeg stopped by it)
  }
  if (!made.made && o.frames.empty() && fs::exists(movie, ec))
    std::printf("note       %s is from an earlier render, not of these images\n", movie.c_str());
  return kExitOk;
}

}  // namespace pd
