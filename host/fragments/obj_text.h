// Fast text for the OBJ writers: numbers by std::to_chars (shortest round trip of 9 significant
// digits for coordinates, as %.9g), lines formatted in parallel chunks and joined in order, so
// that a shattered body's millions of faces are written in a fraction of a second.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <string>
#include <vector>

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

// The text of lines 0 .. n-1, `line(out, i)` appending line i, formatted in parallel chunks.
template <class Line>
std::string format_lines(size_t n, Line line) {
  constexpr size_t kChunk = 1 << 14;
  const int64_t chunks = int64_t((n + kChunk - 1) / kChunk);
  std::vector<std::string> part(static_cast<size_t>(chunks));
#pragma omp parallel for schedule(dynamic, 1)
  for (int64_t c = 0; c < chunks; ++c)
    for (size_t i = size_t(c) * kChunk; i < std::min(n, size_t(c + 1) * kChunk); ++i)
      line(part[size_t(c)], i);
  size_t total = 0;
  for (const std::string& p : part) total += p.size();
  std::string out;
  out.reserve(total);
  for (const std::string& p : part) out += p;
  return out;
}

}  // namespace pd
