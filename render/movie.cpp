#include "render/movie.h"

#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

extern char** environ;

namespace pd {

namespace {

// Sends `bytes` to the socket `fd` whole, never raising SIGPIPE; false when the reader went away
// or the send failed.
bool send_all(int fd, const char* bytes, size_t n) {
  while (n > 0) {
    const ssize_t w = ::send(fd, bytes, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    bytes += w;
    n -= size_t(w);
  }
  return true;
}

// Runs argv[0] (a full path) with the arguments, its standard input a socket fed with the bytes of
// `inputs` in order, and waits; returns its exit status, or -1 when it could not be started, did
// not exit normally, or an input could not be read. (A socket, not a pipe: a program that stops
// reading ends the feeding with an error instead of a SIGPIPE for the whole process.)
int run_program_fed(const std::vector<std::string>& args, const std::vector<std::string>& inputs) {
  std::vector<char> buffer(1 << 20);
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return -1;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[0]);
  bool fed = spawned == 0;
  for (size_t k = 0; fed && k < inputs.size(); ++k) {
    std::ifstream in(inputs[k], std::ios::binary);
    fed = bool(in);
    while (fed && in) {
      in.read(buffer.data(), std::streamsize(buffer.size()));
      fed = send_all(fds[1], buffer.data(), size_t(in.gcount()));
    }
  }
  ::close(fds[1]);  // (end of input)
  if (spawned != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (!fed || !WIFEXITED(status)) return -1;
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

MovieResult make_movie(const std::vector<std::string>& images, const std::string& target, int framerate) {
  namespace fs = std::filesystem;
  MovieResult r;
  const std::string ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) {
    r.message = "no movie: ffmpeg is not on PATH (install it, e.g. apt-get install ffmpeg, to get " +
                fs::path(target).filename().string() + ")";
    return r;
  }
  if (images.empty()) {
    r.message = "no movie: no images";
    return r;
  }
  const std::string temporary = target + ".tmp." + std::to_string(::getpid()) + ".0";
  const int status = run_program_fed({ffmpeg,       "-hide_banner", "-loglevel",
                                      "error",      "-y",           "-f",
                                      "image2pipe", "-framerate",   std::to_string(framerate),
                                      "-c:v",       "png",          "-i",
                                      "pipe:0",     "-vf",          "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                      "-pix_fmt",   "yuv420p",      "-c:v",
                                      "libx264",    "-f",           "mp4",
                                      temporary},
                                     images);
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
