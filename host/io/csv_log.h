// A per-frame table (energy.csv, fragments.csv): a header and one line per frame, held in memory
// and rewritten atomically after every line, so an interrupted run leaves whole lines only. A
// resumed run continues from the text its checkpoint kept.
#pragma once

#include <string>
#include <utility>

#include "host/io/atomic_file.h"

namespace pd {

class CsvLog {
 public:
  CsvLog(std::string path, std::string header) : path_(std::move(path)), text_(std::move(header)) {}
  // Appends `line` (ending in a line break) and rewrites the file.
  void add(const std::string& line) {
    text_ += line;
    write_file_atomic(path_, text_);
  }
  const std::string& text() const { return text_; }
  // The checkpointed text (rewritten at the next add).
  void restore(std::string text) { text_ = std::move(text); }

 private:
  std::string path_, text_;
};

}  // namespace pd
