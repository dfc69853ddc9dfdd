#include "host/io/record_file.h"

#include <cerrno>
#include <cstring>

#include "host/io/checksum.h"
#include "host/io/input_file.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "record files are little endian");

namespace pd {

namespace {

constexpr size_t kNameBytes = 16;

template <class T>
void append(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

void RecordWriter::add(const std::string& name, std::string_view bytes) {
  if (name.empty() || name.size() > kNameBytes) throw std::invalid_argument("bad record name '" + name + "'");
  records_.emplace_back(name, bytes);
}

void RecordWriter::add_owned(const std::string& name, std::string bytes) {
  owned_.push_back(std::move(bytes));
  add(name, owned_.back());
}

void RecordWriter::write(const std::string& path, const char (&magic)[8], uint32_t version) const {
  // The header and record table are small; the checksum runs over the bytes as they stream out.
  write_file_atomic(path, [&](std::ostream& out) {
    uint64_t hash = kFnvOffset;
    auto emit = [&](std::string_view b) {
      hash = fnv1a(b, hash);
      out.write(b.data(), std::streamsize(b.size()));
    };
    std::string head(magic, 8);
    append(head, version);
    emit(head);
    for (const auto& [name, bytes] : records_) {
      std::string entry(kNameBytes, '\0');
      entry.replace(0, name.size(), name);
      append(entry, uint64_t(bytes.size()));
      emit(entry);
      emit(bytes);
    }
    std::string tail;
    append(tail, hash);
    out.write(tail.data(), std::streamsize(tail.size()));
  });
}

RecordReader::RecordReader(const std::string& path, const char (&magic)[8], uint32_t version) : path_(path) {
  std::string why;
  std::optional<std::string> bytes = read_output_file(path, why);
  if (!bytes) throw io_error("read", path, why);
  data_ = std::move(*bytes);

  // Header, then the checksum over everything but its own 8 bytes.
  const size_t head = 8 + sizeof(uint32_t);
  if (data_.size() < head + sizeof(uint64_t)) fail("truncated (" + std::to_string(data_.size()) + " bytes)");
  if (std::memcmp(data_.data(), magic, 8) != 0) fail("not a perifrac checkpoint (wrong magic)");
  uint32_t got_version;
  std::memcpy(&got_version, data_.data() + 8, sizeof got_version);
  if (got_version != version)
    fail("format version " + std::to_string(got_version) + ", this build reads version " +
         std::to_string(version));
  const size_t body_end = data_.size() - sizeof(uint64_t);
  uint64_t stored;
  std::memcpy(&stored, data_.data() + body_end, sizeof stored);
  if (fnv1a(std::string_view(data_).substr(0, body_end)) != stored)
    fail("checksum mismatch: the file is corrupted or truncated");

  // Record table.
  size_t at = head;
  while (at < body_end) {
    if (body_end - at < kNameBytes + sizeof(uint64_t)) fail("record table runs past the end");
    std::string name(data_.data() + at, strnlen(data_.data() + at, kNameBytes));
    uint64_t length;
    std::memcpy(&length, data_.data() + at + kNameBytes, sizeof length);
    at += kNameBytes + sizeof(uint64_t);
    if (length > body_end - at) fail("record '" + name + "' runs past the end");
    if (!records_.emplace(name, std::string_view(data_).substr(at, length)).second)
      fail("record '" + name + "' appears twice");
    at += length;
  }
}

std::string_view RecordReader::get(const std::string& name) const {
  const auto it = records_.find(name);
  if (it == records_.end()) fail("record '" + name + "' is missing");
  return it->second;
}

void RecordReader::fail(const std::string& reason) const {
  // (The reason may quote bytes of the file: control characters become '?', so it stays one line.)
  std::string printable = reason;
  for (char& c : printable)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  throw io_error("read", path_, printable);
}

}  // namespace pd
