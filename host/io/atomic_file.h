// Crash-safe file output: a target file is either left as it was or replaced whole, never
// half-written. Every output file of a run (frames, series index, summaries) goes through here.
#pragma once

#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pd {

// An input/output failure. The message names the path and the reason, e.g.
// "cannot write 'out/frame_00003.vtu': No space left on device".
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Builds the IoError "cannot <verb> '<path>': <reason>".
IoError io_error(std::string_view verb, const std::string& path, const std::string& reason);
// Same, with the reason taken from an errno value.
IoError io_error_errno(std::string_view verb, const std::string& path, int err);

// Writes `path` atomically: `write` fills a temporary file in the same directory (its name holds
// ".tmp"), which is checked, fsync'ed and renamed over `path`. On any failure (an OS error, the
// stream left failed by `write`, or an exception thrown by `write`) the temporary is removed and
// `path` is untouched; OS errors and failed streams throw IoError, other exceptions pass through.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);
void write_file_atomic(const std::string& path, std::string_view bytes);

// The output journal: a callback told of every file about to appear under its final name (before
// the rename), so that a run's folder knows each file its run wrote (host/app/run_folder.h). One
// at a time per process; an empty function removes it. Thread-safe.
using OutputObserver = std::function<void(const std::string& path)>;
void set_output_observer(OutputObserver observer);
// Tells the observer that `path` is about to appear: write_file_atomic does; a writer that renames
// into place itself (the movie, made by ffmpeg) is announced by its caller beforehand.
void announce_output(const std::string& path);

// The raw bytes of a vector's elements (host byte order), e.g. to write them out.
template <class T>
std::string_view bytes_of(const std::vector<T>& v) {
  return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
}

// Removes the temporaries that write_file_atomic left in `dir` when its process was killed
// mid-write ("<name>.tmp.<pid>.<n>" of processes no longer running). Returns how many.
size_t remove_stale_temporaries(const std::string& dir);

// Creates `dir` and its missing parents; does nothing if it already is a directory. Throws
// IoError when it cannot (e.g. a component of the path is a regular file).
void ensure_directory(const std::string& dir);

}  // namespace pd
