#include "render/movie.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <vector>

extern char** environ;

namespace pd {

namespace {

// `path` with the characters glob(3) treats specially escaped by a backslash.
std::string glob_escape(const std::string& path) {
  std::string out;
  for (char c : path) {
    if (c == '*' || c == '?' || c == '[' || c == ']' || c == '{' || c == '}' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

// Runs argv[0] (a full path) with the arguments and waits; returns its exit status, or -1 when it
// could not be started or did not exit normally.
int run_program(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace

std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0 && !std::filesystem::is_directory(candidate)) return candidate;
  }
  return "";
}

MovieResult make_movie(const std::string& image_dir, int framerate) {
  namespace fs = std::filesystem;
  MovieResult r;
  const std::string ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) {
    r.message = "no movie: ffmpeg is not on PATH (install it, e.g. apt-get install ffmpeg, to get " +
                std::string(kMovieFileName) + ")";
    return r;
  }
  const std::string target = (fs::path(image_dir) / kMovieFileName).string();
  const std::string temporary = target + ".tmp." + std::to_string(::getpid()) + ".0";
  const int status = run_program({ffmpeg,
                                  "-nostdin",
                                  "-hide_banner",
                                  "-loglevel",
                                  "error",
                                  "-y",
                                  "-framerate",
                                  std::to_string(framerate),
                                  "-pattern_type",
                                  "glob",
                                  "-i",
                                  glob_escape(fs::path(image_dir).string()) + "/frame_*.png",
                                  "-vf",
                                  "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                  "-pix_fmt",
                                  "yuv420p",
                                  "-c:v",
                                  "libx264",
                                  "-f",
                                  "mp4",
                                  temporary});
  std::error_code ec;
  if (status != 0) {
    fs::remove(temporary, ec);
    r.message =
        "no movie: ffmpeg failed (" +
        (status < 0 ? std::string("did not run to the end") : "exit status " + std::to_string(status)) + ")";
    return r;
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    fs::remove(temporary, ec);
    r.message = "no movie: cannot rename the encoded file to '" + target + "'";
    return r;
  }
  r.made = true;
  r.message = target;
  return r;
}

}  // namespace pd
