// `perifrac render DIR`: turn the frames of a run into images (frame_primitives.h says what each
// particle becomes) and, when ffmpeg is on PATH, a movie. RunRenderer renders one frame file at a
// time, so that `perifrac run` can render as it goes (live_render.h).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/app/frame_primitives.h"
#include "host/app/mesh_surface.h"
#include "host/app/run_folder.h"
#include "host/scene/scene.h"
#include "render/renderer.h"

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
  std::string material = "opaque";  // opaque | glass: the material of every body without a look
  std::vector<std::optional<BodyLook>> body_looks;  // per body id: the scene's [render.bodies]
  bool damage_colors = false;                       // tint damaged particles red
  // "elements": every particle drawn as its element. "mesh": the bodies in a frame's crack mesh
  // (crack_mesh_NNNNN.ply) drawn from its triangles, smooth-shaded (mesh_surface.h); a frame
  // without that file is an error.
  std::string surface = "elements";
  int smooth_cracks = kDefaultCrackSmoothing;  // Taubin passes over the crack surfaces (mesh only)
  real ior = real(1.5);                        // glass index of refraction
  std::string environment = "sky";             // "sky" (procedural) or the path of a Radiance .hdr map
  bool movie = true;            // DIR/render/movie.mp4 when ffmpeg is on PATH (all frames only)
  std::vector<int64_t> frames;  // frame numbers to render; empty: every frame of the run
  // A finished run's folder: a file its journal lists must be there (a run rendering as it goes
  // does not hold it to its journal, which a resume rewrites).
  bool check_run_files = true;
  // `perifrac render`: the options given on the command line (their long names); the others take
  // the run's scene's [render] block where it has one (render_frames).
  std::vector<std::string> given;
};

// The options of a scene's [render] block (which it must have) for the run folder `dir`.
RenderOptions render_options_from_scene(const Scene& scene, const std::string& dir);

// The run's complete frame files frame_NNNNN.pfr (complete_frame_files), in order; with `wanted`
// (frame numbers), only those, each once. `note`: the frames left out as incomplete, if any.
// Throws IoError when the folder cannot be listed or a frame the run wrote is gone,
// std::invalid_argument naming a wanted frame the run does not have (and the range it has).
std::vector<std::string> select_frame_files(const std::string& dir, const RunContents& run,
                                            const std::vector<int64_t>& wanted, std::string* note);

// Throws std::invalid_argument naming the option and what is allowed when `o` holds a bad value
// (image size, spp, field of view, material, ior, surface, smoothing passes, eye at look-at).
void check_render_options(const RenderOptions& o);

// What one rendered frame took.
struct FrameRenderReport {
  std::string png;
  KdTreeStats tree;
  int64_t hidden = 0;     // tetrahedra left out of the kd-tree (hidden_tets.h)
  int64_t triangles = 0;  // crack mesh triangles drawn (--surface mesh)
  double render_seconds = 0;
  int64_t rays = 0;
};

// The renderer of one run folder: rest.pfr, trimtopes.ptm and tets.ptt are read once, the
// environment loaded and the backend chosen at construction; each render() call draws one frame
// file. Throws IoError for unreadable inputs (a file the run wrote that is gone included) and
// std::invalid_argument for bad options (an unreadable .hdr included) or frames that do not match the rest
// file.
class RunRenderer {
 public:
  // `last_frame`: a frame file whose lowest cube sets the default floor (empty: the rest only).
  RunRenderer(const RenderOptions& options, const std::string& last_frame);
  ~RunRenderer();

  // Throws std::invalid_argument with --surface mesh when the frame's crack mesh is missing or
  // does not name its faces' particles.
  FrameRenderReport render(const std::string& frame_file);
  const std::string& image_dir() const { return out_; }
  std::string device() const;         // "<device name> [<backend>]"
  std::string scene_summary() const;  // counts of each primitive kind and the material
  const std::string& backend_note() const { return backend_note_; }

 private:
  RenderOptions options_;
  std::string out_, backend_note_;
  RestData rest_;
  std::optional<RestTrimtopes> trimtopes_;
  std::optional<EmbeddedTets> tets_;
  Camera camera_;
  // --surface mesh: the frame's crack mesh appended to its primitives (the covered particles'
  // flags set in `left_out`); returns the triangles added.
  int64_t add_crack_mesh(int64_t frame, const std::vector<int32_t>& body, PrimitiveSet* prims,
                         std::vector<Vec3>* albedo, std::vector<uint8_t>* material,
                         std::vector<uint8_t>* left_out) const;
  RenderSettings settings_;
  std::unique_ptr<Renderer> renderer_;
  std::string backend_name_;
  RunContents run_;  // the files the run wrote
  // DIR/relative where it is; nullopt where the run did not write it; IoError where it did and
  // the file is gone.
  std::optional<std::string> run_file(const std::string& relative) const;
  // The mesh colliders' distance grids for drawing, built from colliders.obj when a frame first
  // has one (grid fields of collider k in mesh_grid_[k], shape mesh_grid_[k].shape == kColliderMesh).
  void add_mesh_grids(std::vector<Collider>& colliders);
  std::vector<TriMesh> collider_shapes_;
  std::vector<Collider> mesh_grid_;
  std::vector<float> collider_grids_;
};

// Renders DIR/render/frame_NNNNN.png for every complete frame file, printing one line per frame
// with the rays per second, then the movie. Returns kExitOk, or kExitInterrupted when SIGINT or
// SIGTERM stopped it between two frames; throws as RunRenderer does.
int render_frames(const RenderOptions& options);

}  // namespace pd
