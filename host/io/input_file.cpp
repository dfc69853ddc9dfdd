#include "host/io/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace pd {
namespace {

constexpr size_t kMegabyte = size_t(1) << 20;
constexpr size_t kDefaultLimitMb = 1024;

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a pipe";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a plain file";
}

}  // namespace

size_t input_limit_bytes() {
  const char* text = std::getenv("PERIFRAC_MAX_INPUT_MB");
  if (!text || !*text) return kDefaultLimitMb * kMegabyte;
  char* end = nullptr;
  errno = 0;
  const unsigned long long mb = std::strtoull(text, &end, 10);
  if (*end != '\0' || text[0] == '-' || errno == ERANGE || mb == 0 || mb > (~size_t(0)) / kMegabyte)
    throw std::invalid_argument(std::string("PERIFRAC_MAX_INPUT_MB: '") + text +
                                "' is not allowed (allowed: a whole number of megabytes from 1)");
  return size_t(mb) * kMegabyte;
}

namespace {

// A regular file read whole, at most `limit` bytes (none: its size when opened); `limit_text`
// names the limit in the messages.
std::optional<std::string> read_regular_file(const std::string& path, std::string& why,
                                             std::optional<size_t> limit_bytes,
                                             const std::string& limit_text) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {  // (follows symlinks: their target must be a file)
    why = std::strerror(errno);
    return std::nullopt;
  }
  if (!S_ISREG(st.st_mode)) {
    why = std::string("not a regular file (") + kind_of(st.st_mode) + "; allowed: a regular file)";
    return std::nullopt;
  }
  const size_t limit = limit_bytes ? *limit_bytes : size_t(st.st_size);
  if (size_t(st.st_size) > limit) {
    why = "the file is " + std::to_string(size_t(st.st_size) / kMegabyte) + " MB, larger than " + limit_text;
    return std::nullopt;
  }
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) {
    why = std::strerror(errno);
    return std::nullopt;
  }
  std::string bytes;
  char buf[1 << 16];
  size_t got = 0;
  while ((got = std::fread(buf, 1, sizeof buf, file.get())) > 0) {
    if (bytes.size() + got > limit) {
      why = "the file grew past " + limit_text + " while it was read";
      return std::nullopt;
    }
    bytes.append(buf, got);
  }
  if (std::ferror(file.get())) {
    why = std::strerror(errno);
    return std::nullopt;
  }
  return bytes;
}

}  // namespace

std::optional<std::string> read_input_file(const std::string& path, std::string& why) {
  const size_t limit = input_limit_bytes();
  return read_regular_file(
      path, why, limit,
      "the input limit of " + std::to_string(limit / kMegabyte) + " MB (PERIFRAC_MAX_INPUT_MB)");
}

bool is_bounded_input(const std::string& path, std::string& why) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    why = std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    why = std::string("not a regular file (") + kind_of(st.st_mode) + "; allowed: a regular file)";
    return false;
  }
  const size_t limit = input_limit_bytes();
  if (size_t(st.st_size) > limit) {
    why = "the file is " + std::to_string(size_t(st.st_size) / kMegabyte) +
          " MB, larger than the input limit of " + std::to_string(limit / kMegabyte) +
          " MB (PERIFRAC_MAX_INPUT_MB)";
    return false;
  }
  return true;
}

std::optional<std::string> read_output_file(const std::string& path, std::string& why) {
  return read_regular_file(path, why, std::nullopt, "its size when opened");
}

}  // namespace pd
