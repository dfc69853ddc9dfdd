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
#include <map>
#include <mutex>
#include <optional>
#include <set>
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

// What a run's folder holds for the commands that read it (render, compare): the manifest's last
// complete frame and the files its journal lists.
struct RunContents {
  std::optional<int64_t> frames_written;  // the manifest's; nullopt: a folder without a manifest
  std::set<std::string> files;            // the journal's paths, relative to the folder
  // Whether the run wrote `relative` (false for a folder without a journal).
  bool wrote(const std::string& relative) const { return files.count(relative) > 0; }
};

// Reads DIR's manifest and journal (either may be missing). Throws IoError for a broken manifest.
RunContents read_run_contents(const std::string& dir);

// The frame files DIR holds complete (frame_NNNNN.pfr), by frame number: those up to the
// manifest's frames written (without a manifest, every one there). The numbers of those past it
// (the frame a killed run was writing, or the one a running run is writing) go to `partial`.
// Throws IoError naming a frame file the run wrote (its journal says) that is gone, and when the
// folder cannot be listed.
std::map<int64_t, std::string> complete_frame_files(const std::string& dir, const RunContents& run,
                                                    std::vector<int64_t>* partial);

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
  std::set<std::string> recorded_;  // the paths the journal holds
  std::mutex recorded_mutex_;
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
