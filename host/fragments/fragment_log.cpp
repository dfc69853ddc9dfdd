#include "host/fragments/fragment_log.h"

#include <cstdio>

namespace pd {

namespace {

std::string header() {
  std::string h = "frame,step,time,fragments,singles,single_mass_share,largest_mass_share,largest_particles";
  for (int b = 0; b < kFragmentLogBins; ++b) {
    const int64_t lo = int64_t(1) << b, hi = (int64_t(2) << b) - 1;
    h += ",n_" + std::to_string(lo) +
         (b + 1 == kFragmentLogBins ? "_up"
          : lo == hi                ? ""
                                    : "_" + std::to_string(hi));
  }
  return h + ",free_mass_share\n";
}

}  // namespace

FragmentLog::FragmentLog(std::string path) : log_(std::move(path), header()) {}

void FragmentLog::add(int64_t frame, int64_t step, double time, const ComponentStats& s) {
  char line[192];
  const double total = s.mass > 0 ? s.mass : 1;
  std::snprintf(line, sizeof line, "%lld,%lld,%.9g,%zu,%lld,%.6g,%.6g,%d", (long long)frame, (long long)step,
                time, s.count, (long long)s.singles, s.single_mass / total, s.largest_mass / total,
                s.largest);
  std::string row = line;
  for (int b = 0; b < kFragmentLogBins; ++b) {
    int64_t n = 0;
    for (size_t k = size_t(b); k < s.histogram.size() && (k == size_t(b) || b + 1 == kFragmentLogBins); ++k)
      n += s.histogram[k];  // (the last bin takes every larger one)
    row += "," + std::to_string(n);
  }
  if (s.free_counted) {
    std::snprintf(line, sizeof line, ",%.6g", s.free_mass / total);
    row += line;
  } else {
    row += ",";
  }
  log_.add(row + "\n");
}

void FragmentLog::restore(std::string text) {
  // A checkpoint's text from before free_mass_share: its header and rows get the column, empty.
  const std::string now = header();
  const size_t end = text.find('\n');
  if (end != std::string::npos && text.compare(0, end + 1, now) != 0 &&
      now.compare(0, end, text, 0, end) == 0 && now.size() > end + 1) {
    std::string upgraded = now;
    for (size_t at = end + 1; at < text.size();) {
      const size_t eol = text.find('\n', at);
      const size_t stop = eol == std::string::npos ? text.size() : eol;
      upgraded += text.substr(at, stop - at) + ",\n";
      at = stop + 1;
    }
    text = std::move(upgraded);
  }
  log_.restore(std::move(text));
}

}  // namespace pd
