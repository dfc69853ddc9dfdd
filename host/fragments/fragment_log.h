// fragments.csv: the run's fragment statistics, one row per frame, so that an artist tunes the
// look of the breakage by numbers (scripts/plot-fragments.sh draws it). Columns:
//   frame, step, time           where the row is
//   fragments, singles          pieces, and pieces of one particle (dust)
//   single_mass_share           mass in single particles / total mass
//   largest_mass_share          mass of the heaviest piece / total mass
//   largest_particles           particles of the largest piece
//   n_1, n_2_3, n_4_7, ...      pieces of 2^b to 2^(b+1)-1 particles (the last bin open-ended)
//   free_mass_share             mass in particles without an intact bond / total mass (the singles
//                               less those still held by a bond across an edge or corner)
// Rewritten atomically after every frame; a resumed run continues from its checkpoint's text (a
// text from before the last column gets the column, empty in its rows).
#pragma once

#include <cstdint>
#include <string>

#include "host/fragments/components.h"
#include "host/io/csv_log.h"

namespace pd {

inline constexpr const char* kFragmentLogFileName = "fragments.csv";
inline constexpr int kFragmentLogBins = 24;  // up to the open bin of 2^23 = 8,388,608 particles

class FragmentLog {
 public:
  explicit FragmentLog(std::string path);
  void add(int64_t frame, int64_t step, double time, const ComponentStats& s);
  const std::string& text() const { return log_.text(); }
  // Continues a resumed run's log from its checkpointed text (rewritten at the next add).
  void restore(std::string text);

 private:
  CsvLog log_;
};

}  // namespace pd
