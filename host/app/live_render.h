// `perifrac run` with a [render] block: each N-th frame is rendered to OUT/render/ right after
// the run wrote it, and the movie is made at the end (ffmpeg permitting).
#pragma once

#include <memory>
#include <string>

#include "host/app/render_frames.h"
#include "host/scene/scene.h"

namespace pd {

class LiveRender {
 public:
  // The run's output folder must already hold rest.pfr (and trimtopes.ptm / tets.ptt where the
  // scene has such bodies). The floor is the scene's world floor when it has one. Throws
  // SceneError naming render.environment for an unusable .hdr, and render for other bad values.
  LiveRender(const Scene& scene, const std::string& out_dir, const std::string& backend);

  // Renders OUT/frame_NNNNN.pfr when frame is a multiple of `every` (the first time, after the
  // earlier frames' missing images: a run resumed after an interrupt mid-image). An interrupt
  // leaves the image unfinished and unwritten.
  void frame(int64_t frame);
  // One summary line, then the movie of the run's rendered frames, those of a run resumed
  // included (or why there is none).
  void finish();

 private:
  void draw(int64_t frame);
  std::string out_dir_;
  int64_t every_ = 1;
  std::unique_ptr<RunRenderer> renderer_;
  int64_t frames_ = 0, rays_ = 0, last_frame_ = -1;
  bool caught_up_ = false;  // the earlier frames' missing images drawn (frame's first call)
  double build_seconds_ = 0, render_seconds_ = 0;
};

}  // namespace pd
