#include "host/app/run_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "host/io/atomic_file.h"
#include "host/io/exact_number.h"
#include "host/io/frame.h"
#include "host/io/input_file.h"

namespace pd {

namespace fs = std::filesystem;

namespace {

std::string manifest_text(const RunManifest& m) {
  std::ostringstream t;
  t << "perifrac " << PERIFRAC_VERSION << "\n"
    << "scene_path " << m.scene_path << "\n"
    << "scene_hash " << m.scene_hash << "\n"
    << "scale " << exact_number(m.scale) << "\n"
    << "overrides " << m.overrides.size() << "\n";
  for (size_t k = 0; k < m.overrides.size(); ++k) t << "override_" << k << " " << m.overrides[k] << "\n";
  t << "frames_written " << m.frames_written << "\n";
  return t.str();
}

// A file of the folder: its bytes, or nothing when it does not exist; a file that cannot be read
// is a RunFolderError.
std::optional<std::string> read_folder_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return std::nullopt;
  std::string why;
  std::optional<std::string> bytes = read_input_file(path, why);
  if (!bytes) throw RunFolderError("cannot read '" + path + "': " + why);
  return bytes;
}

// One journal entry: the frame a file was written for and its path relative to the folder.
struct JournalEntry {
  int64_t frame;
  std::string path;
};

// The journal's entries; lines that are not "<frame> <relative path>" (a torn last line of a
// killed run) are skipped, and so are paths that would leave the folder.
std::vector<JournalEntry> read_journal(const std::string& dir) {
  std::vector<JournalEntry> entries;
  const std::optional<std::string> text = read_folder_file(dir + "/" + kJournalFileName);
  if (!text) return entries;
  std::istringstream in(*text);
  for (std::string line; std::getline(in, line);) {
    const size_t space = line.find(' ');
    if (space == std::string::npos || space == 0 || space + 1 == line.size()) continue;
    char* end = nullptr;
    const long long frame = std::strtoll(line.c_str(), &end, 10);
    if (end != line.c_str() + space) continue;
    const fs::path path = fs::path(line.substr(space + 1)).lexically_normal();
    if (path.is_absolute() || path.empty() || *path.begin() == "..") continue;
    entries.push_back({int64_t(frame), path.string()});
  }
  return entries;
}

// The first frame each journaled file was written for.
std::map<std::string, int64_t> first_frames(const std::vector<JournalEntry>& entries) {
  std::map<std::string, int64_t> first;
  for (const JournalEntry& e : entries) {
    const auto [it, added] = first.emplace(e.path, e.frame);
    if (!added) it->second = std::min(it->second, e.frame);
  }
  return first;
}

// Removes `relative` from `dir` and the folders it leaves empty on the way up (not `dir`).
bool remove_output(const std::string& dir, const std::string& relative) {
  std::error_code ec;
  const fs::path path = fs::path(dir) / relative;
  if (fs::is_directory(fs::symlink_status(path, ec)) || !fs::remove(path, ec)) return false;
  for (fs::path parent = fs::path(relative).parent_path(); !parent.empty(); parent = parent.parent_path())
    if (!fs::remove(fs::path(dir) / parent, ec)) break;  // (only removes an empty folder)
  return true;
}

// Moves `relative` out of `dir` to `aside` (on the same file system: a rename), removing the
// folders it leaves empty on the way up (not `dir`); removes it where it cannot be moved.
bool set_aside(const std::string& dir, const std::string& relative, const fs::path& aside) {
  std::error_code ec;
  const fs::path path = fs::path(dir) / relative;
  if (fs::is_directory(fs::symlink_status(path, ec))) return false;
  fs::rename(path, aside, ec);
  if (ec) return remove_output(dir, relative);
  for (fs::path parent = fs::path(relative).parent_path(); !parent.empty(); parent = parent.parent_path())
    if (!fs::remove(fs::path(dir) / parent, ec)) break;  // (only removes an empty folder)
  return true;
}

// The folders of files set aside in `dir`, this process's and any a killed run left.
std::vector<fs::path> removing_folders(const std::string& dir) {
  std::vector<fs::path> folders;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().rfind(kRemovingFolderPrefix, 0) == 0 && e.is_directory(ec))
      folders.push_back(e.path());
  return folders;
}

// Whether the folder holds a run's outputs without a manifest (a perifrac from before manifests):
// those files cannot be told from the user's, so the folder is refused rather than mixed.
std::string unmanaged_run_file(const std::string& dir) {
  std::error_code ec;
  for (const char* name : {"checkpoint.pck", "rest.pfr", "particles.pvd", "energy.csv", "frame_00000.pfr",
                           "frame_00000.vtu", "fragments.obj"})
    if (fs::exists(fs::path(dir) / name, ec)) return name;
  return "";
}

// The lock's holder as its lock file says ("process N"), for the message.
std::string lock_holder(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  const long pid = n > 0 ? std::strtol(text, nullptr, 10) : 0;
  return pid > 0 ? "process " + std::to_string(pid) : "another process";
}

}  // namespace

std::optional<RunManifest> read_manifest(const std::string& dir) {
  const std::string path = dir + "/" + kManifestFileName;
  const std::optional<std::string> text = read_folder_file(path);
  if (!text) return std::nullopt;
  std::map<std::string, std::string> kv;
  std::istringstream in(*text);
  for (std::string line; std::getline(in, line);) {
    const size_t space = line.find(' ');
    if (space != std::string::npos) kv[line.substr(0, space)] = line.substr(space + 1);
  }
  const auto broken = [&](const std::string& key) {
    return RunFolderError("'" + path + "' is broken (its key '" + key +
                          "' is missing or malformed): remove the folder, or give another --out");
  };
  const auto get = [&](const std::string& key) -> const std::string& {
    const auto it = kv.find(key);
    if (it == kv.end()) throw broken(key);
    return it->second;
  };
  const auto integer = [&](const std::string& key) {
    const std::string& v = get(key);
    char* end = nullptr;
    errno = 0;
    const long long x = std::strtoll(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE) throw broken(key);
    return int64_t(x);
  };
  RunManifest m;
  m.scene_path = get("scene_path");
  {
    const std::string& v = get("scene_hash");
    char* end = nullptr;
    m.scene_hash = std::strtoull(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0') throw broken("scene_hash");
  }
  {
    const std::string& v = get("scale");
    char* end = nullptr;
    m.scale = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0') throw broken("scale");
  }
  const int64_t overrides = integer("overrides");
  if (overrides < 0 || size_t(overrides) > kv.size()) throw broken("overrides");
  for (int64_t k = 0; k < overrides; ++k) m.overrides.push_back(get("override_" + std::to_string(k)));
  m.frames_written = integer("frames_written");
  return m;
}

RunContents read_run_contents(const std::string& dir) {
  RunContents run;
  std::optional<RunManifest> manifest;
  try {
    manifest = read_manifest(dir);
  } catch (const RunFolderError& e) {  // (a damaged file of the run, for its readers)
    throw IoError(e.what());
  }
  if (manifest) run.frames_written = manifest->frames_written;
  for (const JournalEntry& e : read_journal(dir)) run.files.insert(e.path);
  return run;
}

std::map<int64_t, std::string> complete_frame_files(const std::string& dir, const RunContents& run,
                                                    std::vector<int64_t>* partial) {
  std::map<int64_t, std::string> frames;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= 10 || name.rfind("frame_", 0) != 0 || it->path().extension() != ".pfr") continue;
    const std::string digits = name.substr(6, name.size() - 10);
    if (digits.size() > 18 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    if (!it->is_regular_file(ec)) continue;
    const int64_t frame = std::stoll(digits);
    if (run.frames_written && frame > *run.frames_written)
      partial->push_back(frame);
    else
      frames.emplace(frame, it->path().string());
  }
  if (ec) throw io_error_errno("list", dir, ec.value());
  std::sort(partial->begin(), partial->end());
  for (int64_t f = 0; run.frames_written && f <= *run.frames_written; ++f) {
    const std::string name = frame_file_name(f, "pfr");
    if (run.wrote(name) && !frames.count(f))
      throw io_error("read", (fs::path(dir) / name).string(),
                     "missing, though the run wrote it (run.files lists it)");
  }
  return frames;
}

std::optional<RunManifest> check_run_folder(const std::string& dir, FolderUse use) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw RunFolderError("output folder '" + dir +
                         "' is a file, not a folder (allowed: --out naming a folder, new or a run's)");
  std::optional<RunManifest> found = read_manifest(dir);
  if (use == FolderUse::kResume) {
    if (!found)
      throw RunFolderError(
          "cannot resume in '" + dir + "': it holds no " + kManifestFileName +
          " (a run of this perifrac writes one first); start the run again with --overwrite instead of "
          "--resume");
    return found;
  }
  if (!found) {
    if (const std::string file = unmanaged_run_file(dir); !file.empty())
      throw RunFolderError("output folder '" + dir + "' holds the outputs of a run that kept no " +
                           kManifestFileName + " (e.g. '" + file +
                           "', written by an older perifrac): remove them, or give another --out");
    return found;
  }
  if (use == FolderUse::kNew && found->frames_written >= 0) {
    std::error_code ec;
    const bool resumable = std::filesystem::exists(dir + "/checkpoint.pck", ec);
    throw RunFolderError(
        "output folder '" + dir + "' holds the run of '" + found->scene_path + "' (frames 0 to " +
        std::to_string(found->frames_written) + "): pass --overwrite to replace it, " +
        (resumable ? "--resume " + dir + " to continue it, " : "") + "or give another --out");
  }
  return found;
}

OutputJournal::OutputJournal(std::string dir) : dir_(std::move(dir)) {
  for (const JournalEntry& e : read_journal(dir_)) recorded_.insert(e.path);
  const std::string path = dir_ + "/" + kJournalFileName;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) throw io_error_errno("write", path, errno);
  set_output_observer([this](const std::string& p) { record(p); });
}

OutputJournal::~OutputJournal() {
  set_output_observer(nullptr);
  ::close(fd_);
}

void OutputJournal::set_frame(int64_t frame) {
  frame_ = frame;
}

// One line per file, in one write(2) on an O_APPEND descriptor, so that a line is whole or absent.
// Files outside the folder and the folder's own bookkeeping files are not journaled, nor a file
// journaled before (rewritten: its first frame, the one a resume goes by, is already there).
void OutputJournal::record(const std::string& path) {
  const fs::path relative =
      fs::path(path).lexically_normal().lexically_relative(fs::path(dir_).lexically_normal());
  if (relative.empty() || *relative.begin() == ".." || relative == kManifestFileName) return;
  {
    const std::lock_guard<std::mutex> lock(recorded_mutex_);  // (writers on several threads)
    if (!recorded_.insert(relative.string()).second) return;
  }
  const std::string line = std::to_string(frame_) + " " + relative.string() + "\n";
  if (::write(fd_, line.data(), line.size()) != ssize_t(line.size())) {
    const int err = errno;
    const std::lock_guard<std::mutex> lock(recorded_mutex_);
    recorded_.erase(relative.string());  // (not journaled: the next write of it tries again)
    throw io_error_errno("write", dir_ + "/" + kJournalFileName, err);
  }
}

RunFolder::RunFolder(std::string dir, FolderUse use) : dir_(std::move(dir)) {
  ensure_directory(dir_);
  const std::string lock_path = dir_ + "/" + kLockFileName;
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw io_error_errno("write", lock_path, errno);
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = lock_holder(lock_fd_);
    ::close(lock_fd_);
    throw RunFolderError("output folder '" + dir_ + "' is in use by a running perifrac (" + holder +
                         "): wait for it to end, or give another --out");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) != ssize_t(pid.size())) {
    const int err = errno;
    ::close(lock_fd_);
    throw io_error_errno("write", lock_path, err);
  }
  // From here on the destructor does not run if the constructor throws: release by hand.
  try {
    if (const size_t stale = remove_stale_temporaries(dir_))
      std::printf("output     removed %zu partial file(s) of an interrupted run\n", stale);
    found_ = check_run_folder(dir_, use);
    if (use != FolderUse::kResume && found_) {
      const bool ended_before_first_frame = found_->frames_written < 0;
      // Replace it: exactly the files its journal lists, then its bookkeeping. The files are moved
      // aside and removed on a thread while the new run goes on: removing a long run's gigabytes
      // took the vase's run 10 s (bench/NOTES.md).
      const fs::path aside = fs::path(dir_) / (kRemovingFolderPrefix + std::to_string(::getpid()));
      std::error_code ec;
      fs::create_directory(aside, ec);
      size_t removed = 0, moved = 0;
      for (const auto& [path, frame] : first_frames(read_journal(dir_)))
        removed += set_aside(dir_, path, aside / std::to_string(moved++));
      fs::remove(fs::path(dir_) / kJournalFileName, ec);
      fs::remove(fs::path(dir_) / kManifestFileName, ec);
      if (!ended_before_first_frame)
        std::printf("output     --overwrite: removed the %zu files of the previous run in %s\n", removed,
                    dir_.c_str());
      found_.reset();
    }
  } catch (...) {
    ::close(lock_fd_);
    throw;
  }
  // The files set aside, and any a killed run left (a resumed run's too), removed beside the run.
  if (const std::vector<fs::path> folders = removing_folders(dir_); !folders.empty())
    remover_ = std::thread([folders] {
      std::error_code ec;
      for (const fs::path& f : folders) fs::remove_all(f, ec);
    });
}

RunFolder::~RunFolder() {
  if (remover_.joinable()) remover_.join();
  journal_.reset();
  ::close(lock_fd_);  // releases the lock; the lock file stays (removing it would race a new run)
}

void RunFolder::start(const RunManifest& manifest) {
  manifest_ = manifest;
  write_manifest();
  if (!journal_) journal_.emplace(dir_);
}

void RunFolder::begin_frame(int64_t frame) {
  journal_->set_frame(frame);
}

void RunFolder::frame_done(int64_t frame) {
  manifest_.frames_written = frame;
  write_manifest();
}

size_t RunFolder::drop_frames_after(int64_t frame) {
  const std::vector<JournalEntry> entries = read_journal(dir_);
  const std::map<std::string, int64_t> first = first_frames(entries);
  size_t removed = 0;
  std::set<std::string> dropped;
  for (const auto& [path, first_frame] : first)
    if (first_frame > frame) {
      removed += remove_output(dir_, path);
      dropped.insert(path);
    }
  // The journal without the dropped files (before the journal is opened for appending again).
  std::string kept;
  for (const JournalEntry& e : entries)
    if (!dropped.count(e.path)) kept += std::to_string(e.frame) + " " + e.path + "\n";
  journal_.reset();
  write_file_atomic(dir_ + "/" + kJournalFileName, kept);
  journal_.emplace(dir_);
  journal_->set_frame(frame);
  frame_done(frame);
  return removed;
}

void RunFolder::write_manifest() {
  write_file_atomic(dir_ + "/" + kManifestFileName, manifest_text(manifest_));
}

}  // namespace pd
