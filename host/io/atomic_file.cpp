#include "host/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <streambuf>
#include <system_error>
#include <vector>

namespace pd {

IoError io_error(std::string_view verb, const std::string& path, const std::string& reason) {
  return IoError("cannot " + std::string(verb) + " '" + path + "': " + reason);
}

IoError io_error_errno(std::string_view verb, const std::string& path, int err) {
  return io_error(verb, path, std::generic_category().message(err));
}

namespace {

// Stream buffer over a POSIX file descriptor that remembers the first write error (errno), so
// the caller can report the OS reason instead of a bare "stream failed".
class FdStreambuf : public std::streambuf {
 public:
  explicit FdStreambuf(int fd) : fd_(fd), buffer_(1 << 16) { reset_put_area(); }
  int error() const { return error_; }

 protected:
  int overflow(int ch) override {
    if (!flush_buffer()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }

  // Small writes are buffered; writes at least as large as the buffer go straight to the file.
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n <= 0) return 0;  // empty arrays may come with a null pointer
    if (n > epptr() - pptr()) {
      if (!flush_buffer()) return 0;
      if (n >= epptr() - pptr()) return write_all(s, size_t(n)) ? n : 0;
    }
    std::memcpy(pptr(), s, size_t(n));
    pbump(int(n));
    return n;
  }

  int sync() override { return flush_buffer() ? 0 : -1; }

 private:
  void reset_put_area() { setp(buffer_.data(), buffer_.data() + buffer_.size()); }

  bool flush_buffer() {
    bool ok = write_all(pbase(), size_t(pptr() - pbase()));
    reset_put_area();
    return ok;
  }

  // Writes all `n` bytes, retrying on EINTR and short writes; false after any error.
  bool write_all(const char* p, size_t n) {
    while (error_ == 0 && n > 0) {
      ssize_t w = ::write(fd_, p, n);
      if (w < 0 && errno != EINTR) error_ = errno;
      if (w > 0) {
        p += w;
        n -= size_t(w);
      }
    }
    return error_ == 0;
  }

  int fd_;
  int error_ = 0;
  std::vector<char> buffer_;
};

// The temporary file beside a target: created on construction, removed on destruction unless
// it has been renamed over the target. Errors name the target, the file the caller asked for.
class TempFile {
 public:
  explicit TempFile(const std::string& target) : target_(target) { open_unique(); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(path_.c_str());
  }

  int fd() const { return fd_; }
  const std::string& path() const { return path_; }

  // Flushes the data to the device and closes the descriptor.
  void sync_and_close() {
    if (::fsync(fd_) != 0) fail(errno);
    int rc = ::close(fd_);
    fd_ = -1;
    if (rc != 0) fail(errno);
  }

  // Renames the (closed) temporary over the target and makes the rename durable (best effort).
  void commit() {
    if (::rename(path_.c_str(), target_.c_str()) != 0) fail(errno);
    committed_ = true;
    sync_parent_directory();
  }

  [[noreturn]] void fail(int err) const { throw io_error_errno("write", target_, err); }

 private:
  // Opens "<target>.tmp.<pid>.<n>" exclusively; n counts up past names left by crashed runs.
  void open_unique() {
    static std::atomic<uint64_t> counter{0};
    for (int attempt = 0; attempt < 100; ++attempt) {
      path_ = target_ + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
      fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ >= 0) return;
      if (errno != EEXIST) break;
    }
    fail(errno);  // the constructor throws, so the destructor never runs: nothing to remove
  }

  // fsync of the directory persists the rename itself; some file systems refuse it, which is
  // harmless because the data is already on disk, so errors are ignored.
  void sync_parent_directory() const {
    std::string dir = std::filesystem::path(target_).parent_path().string();
    int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd < 0) return;
    ::fsync(dfd);
    ::close(dfd);
  }

  std::string target_;
  std::string path_;
  int fd_ = -1;
  bool committed_ = false;
};

std::mutex g_observer_mutex;
OutputObserver g_observer;

}  // namespace

void set_output_observer(OutputObserver observer) {
  const std::lock_guard<std::mutex> lock(g_observer_mutex);
  g_observer = std::move(observer);
}

void announce_output(const std::string& path) {
  const std::lock_guard<std::mutex> lock(g_observer_mutex);
  if (g_observer) g_observer(path);
}

void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
  TempFile tmp(path);

  // Let the caller fill the temporary, then push the buffered tail out and check for errors.
  FdStreambuf buffer(tmp.fd());
  std::ostream out(&buffer);
  write(out);
  out.flush();
  if (buffer.error() != 0) tmp.fail(buffer.error());
  if (!out) throw io_error("write", path, "output stream failed");

  tmp.sync_and_close();
  announce_output(path);
  tmp.commit();
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
  write_file_atomic(path,
                    [bytes](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
}

void ensure_directory(const std::string& dir) {
  if (dir.empty()) return;  // the current directory
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw io_error("create directory", dir, ec.message());
  if (!std::filesystem::is_directory(dir, ec)) {
    throw io_error("create directory", dir, ec ? ec.message() : "exists and is not a directory");
  }
}

size_t remove_stale_temporaries(const std::string& dir) {
  size_t removed = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const size_t at = name.rfind(".tmp.");
    if (at == std::string::npos) continue;
    // "<pid>.<n>" after ".tmp."; the writer's pid must be gone (kill(pid, 0) fails with ESRCH).
    const std::string rest = name.substr(at + 5);
    const size_t dot = rest.find('.');
    if (dot == std::string::npos || dot == 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(rest.c_str(), &end, 10);
    if (end != rest.c_str() + dot || pid <= 0) continue;
    if (pid != long(::getpid()) && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH &&
        std::filesystem::remove(entry.path(), ec))
      ++removed;
  }
  return removed;
}

}  // namespace pd
