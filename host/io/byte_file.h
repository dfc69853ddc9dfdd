// The little-endian binary files of the render side (.tets, .trimtopes): a whole file read into
// memory, values appended to or read from its bytes, every shortfall an IoError naming the file.
#pragma once

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>

#include "host/io/atomic_file.h"

namespace pd {

// Appends v's bytes (host byte order: little-endian on every supported machine).
template <class T>
void put_bytes(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

// The whole file, or an IoError when it cannot be opened.
inline std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error("read", path, "cannot open");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Reads values in order from bytes the caller keeps alive.
class ByteReader {
 public:
  ByteReader(const std::string& path, std::string_view bytes) : path_(path), bytes_(bytes) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  void need(size_t n) const {
    if (bytes_.size() - at_ < n) fail("truncated");
  }
  size_t left() const { return bytes_.size() - at_; }
  [[noreturn]] void fail(const std::string& why) const { throw io_error("read", path_, why); }

 private:
  std::string path_;
  std::string_view bytes_;
  size_t at_ = 0;
};

}  // namespace pd
