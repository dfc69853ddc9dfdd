// ParaView output: one VTK XML UnstructuredGrid (.vtu) per frame, and a .pvd collection that
// lists the frames with their times so the whole run opens as one time series.
#pragma once

#include <string>
#include <vector>

#include "host/io/frame.h"

namespace pd {

// Writes `f` atomically as a .vtu: one VTK_VERTEX cell per particle at its current position,
// point data `velocity`, `damage`, `body`, `id` (particle index) and `component` (only when
// non-empty), field data `TimeValue`; raw appended binary (little endian, UInt64 headers).
// Throws std::invalid_argument for inconsistent sizes, IoError when the file cannot be written.
void write_vtu(const std::string& path, const FrameData& f);

// A triangle surface of several parts: flat float32 points (x y z ...), int32 corners (three per
// triangle) and each triangle's part number.
struct TriangleSurface {
  std::vector<float> points;
  std::vector<int32_t> triangles;
  std::vector<int32_t> part;
};

// Writes `s` atomically as a .vtu of VTK_TRIANGLE cells with cell data `part` and field data
// `TimeValue`, as write_vtu does.
void write_vtu_triangles(const std::string& path, double time, const TriangleSurface& s);

// The series index `<dir>/<name>.pvd`, rewritten atomically after each added frame so that
// ParaView can open the run as a time series at any moment. Nothing is written before add().
class PvdSeries {
 public:
  PvdSeries(const std::string& dir, const std::string& name);

  // Appends the frame `file` (relative to dir, e.g. frame_file_name(f.frame, "vtu")) at `time`
  // and rewrites the index. If the rewrite throws, the series is left as before the call.
  void add(double time, const std::string& file);

  const std::string& path() const { return path_; }
  size_t size() const { return entries_.size(); }

  // The entries so far, and setting them back (a resumed run), which rewrites the index.
  struct Entry {
    double time;
    std::string file;
  };
  const std::vector<Entry>& entries() const { return entries_; }
  void restore(std::vector<Entry> entries);

 private:
  static std::string render(const std::vector<Entry>& entries);

  std::string path_;
  std::vector<Entry> entries_;
};

}  // namespace pd
