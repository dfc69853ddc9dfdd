#include "host/app/live_render.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "host/io/atomic_file.h"
#include "host/io/frame.h"
#include "host/io/interrupt.h"
#include "render/movie.h"

namespace pd {

LiveRender::LiveRender(const Scene& scene, const std::string& out_dir, const std::string& backend)
    : out_dir_(out_dir), every_(scene.render->every) {
  const SceneRender& r = *scene.render;
  RenderOptions o = render_options_from_scene(scene, out_dir);
  o.backend = backend;
  o.check_run_files = false;
  try {
    renderer_ = std::make_unique<RunRenderer>(o, "");
  } catch (const EnvironmentError& e) {
    throw SceneError(scene.path, "render.environment", e.what());
  } catch (const std::invalid_argument& e) {
    throw SceneError(scene.path, "render", e.what());
  }
  std::printf("render     every %lld frame(s), %lld x %lld, %lld spp, %s on %s -> %s\n", (long long)every_,
              (long long)r.width, (long long)r.height, (long long)r.spp, renderer_->scene_summary().c_str(),
              renderer_->device().c_str(), renderer_->image_dir().c_str());
}

void LiveRender::frame(int64_t frame) {
  if (frame % every_ != 0) return;
  // First in this process (a resumed run): the run's earlier images that are missing, those an
  // interrupt left unfinished.
  for (int64_t f = 0; !caught_up_ && f < frame && InterruptGuard::signal_received() == 0; f += every_) {
    if (std::filesystem::exists(renderer_->image_dir() + "/" + frame_file_name(f, "png"))) continue;
    try {
      draw(f);
    } catch (const IoError& e) {  // (an earlier frame's file gone: that image only is missing)
      std::printf("\nrender     frame %lld's image not drawn: %s\n", (long long)f, e.what());
    }
  }
  caught_up_ = true;
  if (InterruptGuard::signal_received() == 0) draw(frame);
}

void LiveRender::draw(int64_t frame) {
  FrameRenderReport r;
  try {
    r = renderer_->render(out_dir_ + "/" + frame_file_name(frame, "pfr"));
  } catch (const Interrupted& e) {  // (the run stops after this frame)
    std::printf(
        "\nrender     %s: its image is not written (a resume draws it, or perifrac render %s --frames "
        "%lld)\n",
        e.what(), out_dir_.c_str(), (long long)frame);
    return;
  }
  ++frames_;
  last_frame_ = std::max(last_frame_, frame);
  rays_ += r.rays;
  build_seconds_ += r.tree.build_seconds;
  render_seconds_ += r.render_seconds;
}

void LiveRender::finish() {
  std::printf("render     %lld frames -> %s (kd-trees %.2f s, rendering %.2f s, %.2f Mrays/s)\n",
              (long long)frames_, renderer_->image_dir().c_str(), build_seconds_, render_seconds_,
              render_seconds_ > 0 ? 1e-6 * double(rays_) / render_seconds_ : 0.0);
  if (frames_ > 0 && InterruptGuard::signal_received() != 0) {
    std::printf("movie      none: interrupted (perifrac render %s makes it)\n", out_dir_.c_str());
  } else if (frames_ > 0) {
    std::vector<std::string> images;  // (the frames before a resume were rendered by the run before it)
    for (int64_t f = 0; f <= last_frame_; f += every_) {
      const std::string image = renderer_->image_dir() + "/" + frame_file_name(f, "png");
      if (std::filesystem::exists(image)) images.push_back(image);
    }
    const std::string movie = renderer_->image_dir() + "/" + kMovieFileName;
    announce_output(movie);
    std::printf("movie      %s\n", make_movie(images, movie).message.c_str());
  }
}

}  // namespace pd
