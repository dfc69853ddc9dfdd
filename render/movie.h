// An MP4 of a run's rendered frames, made by the ffmpeg program when it is on PATH (H.264,
// yuv420p, 24 frames per second by default). ffmpeg is optional: without it the frames stay PNGs.
#pragma once

#include <string>
#include <vector>

namespace pd {

inline constexpr const char* kMovieFileName = "movie.mp4";

// The full path of `program` in a PATH directory, executable; empty when there is none.
std::string find_on_path(const std::string& program);

struct MovieResult {
  bool made = false;
  std::string message;  // the movie's path, or why there is none
};

// Encodes `images` (PNG files, in that order) into `target` (an MP4): ffmpeg reads them from a pipe
// and writes a temporary file beside the target, which is renamed over it only when ffmpeg
// succeeded, so a reader never sees a partial movie. Odd image sizes are padded by one pixel
// (yuv420p needs even sizes).
MovieResult make_movie(const std::vector<std::string>& images, const std::string& target, int framerate = 24);

}  // namespace pd
