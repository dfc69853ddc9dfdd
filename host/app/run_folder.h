// A run's output folder, owned by one run at a time: a lock held for the run's life, a manifest
// written before anything else (scene, hash, scale, --set values, frames written), and a journal
// of every file the run wrote there, so that --overwrite removes exactly the files of the run it
// replaces and a resume removes what was written after its checkpoint: no stale frame survives.
//   run.lock      the lock (flock), holding the running process's id
//   run.manifest  "key value" lines (RunManifest), rewritten atomically after every frame
//   run.files     the journal: "<frame> <path relative to the folder>" per file, appended before
//                 the file appears under its name (frame -1: set-up outputs)
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace pd {

inline constexpr const char* kLockFileName = "run.lock";
inline constexpr const char* kManifestFileName = "run.manifest";
inline constexpr const char* kJournalFileName = "run.files";
// Where --overwrite moves the previous run's files, to be removed while the new run goes on
// (followed by the process id; a folder left by a killed run is removed by the next).
inline constexpr const char* kRemovingFolderPrefix = ".perifrac-removing-";

// A folder that cannot be used for this run; the message names it and what to do.
class RunFolderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RunManifest {
  std::string scene_path;   // absolute
  uint64_t scene_hash = 0;  // scene_fingerprint of the file and the overrides
  double scale = 1;
  std::vector<std::string> overrides;  // --set KEY=VALUE, in order
  int64_t frames_written = -1;         // the last frame whose files are complete; -1: none yet
};

// Reads DIR/run.manifest; nullopt when there is none. Throws RunFolderError for a broken one.
std::optional<RunManifest> read_manifest(const std::string& dir);

// Journals the files written into `dir` while it lives (set_output_observer), tagged with the
// frame being written. One per process at a time.
class OutputJournal {
 public:
  explicit OutputJournal(std::string dir);
  ~OutputJournal();
  OutputJournal(const OutputJournal&) = delete;
  OutputJournal& operator=(const OutputJournal&) = delete;
  // Files announced from now on belong to frame `frame`.
  void set_frame(int64_t frame);

 private:
  void record(const std::string& path);
  std::string dir_;
  int fd_ = -1;
  std::atomic<int64_t> frame_{-1};  // set by the output thread that writes frames, read by every writer
};

enum class FolderUse {
  kNew,        // refuse a folder holding another run's files
  kOverwrite,  // remove the files of the run the folder holds (its journal's), then start afresh
  kResume,     // continue the run the folder holds
};

// What `dir` holds, checked for `use` without taking it (a run checks before its set-up, and again
// once it holds the lock): its manifest, if any. Throws RunFolderError for a folder holding another
// run (kNew), outputs without a manifest (kNew, kOverwrite) or no manifest (kResume).
std::optional<RunManifest> check_run_folder(const std::string& dir, FolderUse use);

class RunFolder {
 public:
  // Makes `dir` and takes its lock (refusing a folder another process runs in), then checks what
  // it holds for `use`: see FolderUse. A folder whose run ended before its first frame is taken
  // over. Throws RunFolderError naming the folder and what to do. A run replaced moves its files
  // aside at once; they are removed on a thread of their own, which the destructor waits for.
  RunFolder(std::string dir, FolderUse use);
  ~RunFolder();
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;

  const std::string& dir() const { return dir_; }
  // The manifest the folder held when opened for kResume.
  const RunManifest& found() const { return *found_; }

  // Writes the manifest and starts the journal: from here on every file written into the folder
  // is recorded (as a set-up output until the first begin_frame).
  void start(const RunManifest& manifest);
  // The files written from now on belong to `frame`.
  void begin_frame(int64_t frame);
  // Frame `frame`'s files are complete: the manifest says so.
  void frame_done(int64_t frame);
  // A resume from the checkpoint of `frame`: removes the files first written for a later frame
  // and sets the manifest's frames written to `frame`. Returns how many files it removed.
  size_t drop_frames_after(int64_t frame);

 private:
  void write_manifest();
  std::string dir_;
  int lock_fd_ = -1;
  std::optional<RunManifest> found_;
  RunManifest manifest_;
  std::optional<OutputJournal> journal_;
  std::thread remover_;  // removes the files moved aside
};

}  // namespace pd
