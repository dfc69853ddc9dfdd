// Named binary records in one file with a checksum, for checkpoints: a corrupted, truncated or
// foreign file is refused as a whole before any record is used.
//   magic (8 bytes) | version u32 | records: name (16 bytes, NUL padded), length u64, bytes |
//   FNV-1a 64 of everything before it
// Little endian; docs/output-formats.md documents the checkpoint's records.
#pragma once

#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "host/io/atomic_file.h"

namespace pd {

// Collects records and writes them in one go. add() and add_array() keep a view only: the
// bytes must outlive write(). add_owned() takes its bytes over.
class RecordWriter {
 public:
  void add(const std::string& name, std::string_view bytes);
  void add_owned(const std::string& name, std::string bytes);
  template <class T>
  void add_array(const std::string& name, const std::vector<T>& v) {
    add(name, bytes_of(v));
  }
  // Writes the records atomically (write_file_atomic); throws IoError naming the path.
  void write(const std::string& path, const char (&magic)[8], uint32_t version) const;

 private:
  std::vector<std::pair<std::string, std::string_view>> records_;
  std::deque<std::string> owned_;  // a deque: its elements never move
};

class RecordReader {
 public:
  // Reads and checks the whole file: magic, version, record table and checksum. Throws
  // IoError "cannot read '<path>': <what is wrong>".
  RecordReader(const std::string& path, const char (&magic)[8], uint32_t version);

  bool has(const std::string& name) const { return records_.count(name) > 0; }
  // The record's bytes; a missing record throws IoError naming it.
  std::string_view get(const std::string& name) const;
  // The record as an array of T; its length must be a multiple of sizeof(T).
  template <class T>
  std::vector<T> get_array(const std::string& name) const {
    const std::string_view b = get(name);
    if (b.size() % sizeof(T) != 0) fail("record '" + name + "' has a length that is not whole elements");
    std::vector<T> v(b.size() / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), b.data(), b.size());
    return v;
  }
  [[noreturn]] void fail(const std::string& reason) const;

 private:
  std::string path_;
  std::string data_;
  std::map<std::string, std::string_view> records_;
};

}  // namespace pd
