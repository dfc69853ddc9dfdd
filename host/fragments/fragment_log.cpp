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
  return h + "\n";
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
  log_.add(row + "\n");
}

}  // namespace pd
