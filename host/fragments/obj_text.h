// Fast text for the OBJ writers: numbers by std::to_chars (shortest round trip of 9 significant
// digits for coordinates, as %.9g), lines formatted in parallel chunks and written in order, so
// that a shattered body's millions of faces are written in a fraction of a second.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "host/io/atomic_file.h"

namespace pd {

// Appends " <v>" with 9 significant digits (like "%.9g").
inline void append_coordinate(std::string& out, double v) {
  char buf[32];
  buf[0] = ' ';
  const auto r = std::to_chars(buf + 1, buf + sizeof buf, v, std::chars_format::general, 9);
  out.append(buf, r.ptr);
}

// Appends " <v>".
inline void append_index(std::string& out, int64_t v) {
  char buf[24];
  buf[0] = ' ';
  const auto r = std::to_chars(buf + 1, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// Appends the text of lines 0 .. n-1 to `parts`, `line(out, i)` appending line i, formatted in
// parallel chunks (each chunk one part, in order).
template <class Line>
void append_lines(std::vector<std::string>& parts, size_t n, Line line) {
  constexpr size_t kChunk = 1 << 14;
  const size_t first = parts.size();
  const int64_t chunks = int64_t((n + kChunk - 1) / kChunk);
  parts.resize(first + size_t(chunks));
#pragma omp parallel for schedule(dynamic, 1)
  for (int64_t c = 0; c < chunks; ++c)
    for (size_t i = size_t(c) * kChunk; i < std::min(n, size_t(c + 1) * kChunk); ++i)
      line(parts[first + size_t(c)], i);
}

// Writes the parts one after the other as the file `path` (atomic, as write_file_atomic; no
// joined copy of a text that can be hundreds of megabytes).
inline void write_parts_atomic(const std::string& path, const std::vector<std::string>& parts) {
  write_file_atomic(path, [&parts](std::ostream& out) {
    for (const std::string& p : parts) out.write(p.data(), std::streamsize(p.size()));
  });
}

}  // namespace pd
