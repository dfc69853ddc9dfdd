// render/byte_file.h: values appended and read back in order, shortfalls and missing files
// reported as IoErrors naming the file.
#include "host/io/byte_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

namespace pd {
namespace {

namespace fs = std::filesystem;

TEST(ByteFile, ValuesComeBackInTheOrderTheyWereAppended) {
  std::string bytes;
  put_bytes(bytes, uint32_t(0xA1B2C3D4u));
  put_bytes(bytes, -2.5f);
  put_bytes(bytes, int64_t(-7));
  put_bytes(bytes, 'x');
  EXPECT_EQ(bytes.size(), 4u + 4u + 8u + 1u);
  EXPECT_EQ(uint8_t(bytes[0]), 0xD4);  // little-endian
  ByteReader r("mem.bin", bytes);
  EXPECT_EQ(r.get<uint32_t>(), 0xA1B2C3D4u);
  EXPECT_EQ(r.get<float>(), -2.5f);
  EXPECT_EQ(r.left(), 9u);
  EXPECT_EQ(r.get<int64_t>(), -7);
  EXPECT_EQ(r.get<char>(), 'x');
  EXPECT_EQ(r.left(), 0u);
}

TEST(ByteFile, ReadingPastTheEndIsAnIoErrorNamingTheFile) {
  const std::string bytes(6, '\0');
  ByteReader r("short.bin", bytes);
  EXPECT_EQ(r.get<uint32_t>(), 0u);
  try {
    r.get<uint32_t>();
    FAIL() << "no error for a truncated read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("short.bin"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  EXPECT_EQ(r.left(), 2u);  // nothing consumed by the failed read
}

TEST(ByteFile, WholeFileIsReadAndAMissingOneNamed) {
  const std::string path =
      (fs::path(::testing::TempDir()) / ("perifrac_bytes_" + std::to_string(getpid()) + ".bin")).string();
  std::string bytes("abc\0def", 7);
  write_file_atomic(path, bytes);
  EXPECT_EQ(read_file_bytes(path), bytes);
  fs::remove(path);
  try {
    read_file_bytes(path);
    FAIL() << "no error for a missing file";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pd
