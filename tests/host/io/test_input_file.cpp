// Bounded input files (host/io/input_file.h): a regular file is read whole; a device (also behind
// a symlink), a directory or a missing file is refused with the reason; a file over
// PERIFRAC_MAX_INPUT_MB is refused without being read; a bad limit is an error naming the variable.
#include "host/io/input_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

// Sets PERIFRAC_MAX_INPUT_MB for the test's life.
class InputLimit {
 public:
  explicit InputLimit(const char* value) { setenv("PERIFRAC_MAX_INPUT_MB", value, 1); }
  ~InputLimit() { unsetenv("PERIFRAC_MAX_INPUT_MB"); }
};

class InputFileTest : public testing::TempDirTest {};

TEST_F(InputFileTest, ReadsARegularFileWhole) {
  std::ofstream(path("a.toml")) << "x = 1\n";
  std::string why;
  const std::optional<std::string> bytes = read_input_file(path("a.toml"), why);
  ASSERT_TRUE(bytes) << why;
  EXPECT_EQ(*bytes, "x = 1\n");
}

TEST_F(InputFileTest, RefusesDevicesDirectoriesAndMissingFiles) {
  std::string why;
  EXPECT_FALSE(read_input_file("/dev/zero", why));
  EXPECT_NE(why.find("not a regular file (a character device"), std::string::npos) << why;
  std::filesystem::create_symlink("/dev/urandom", path("mesh.obj"));
  EXPECT_FALSE(read_input_file(path("mesh.obj"), why));
  EXPECT_NE(why.find("a character device"), std::string::npos) << why;
  std::filesystem::create_directory(path("folder"));
  EXPECT_FALSE(read_input_file(path("folder"), why));
  EXPECT_NE(why.find("a directory"), std::string::npos) << why;
  EXPECT_FALSE(read_input_file(path("missing"), why));
  EXPECT_NE(why.find("No such file"), std::string::npos) << why;
}

TEST_F(InputFileTest, RefusesAFileOverTheLimit) {
  const InputLimit limit("1");
  std::ofstream(path("big.obj")) << std::string(size_t(1) << 21, 'v');  // 2 MB
  std::string why;
  EXPECT_FALSE(read_input_file(path("big.obj"), why));
  EXPECT_NE(why.find("larger than the input limit of 1 MB (PERIFRAC_MAX_INPUT_MB)"), std::string::npos)
      << why;
  EXPECT_EQ(input_limit_bytes(), size_t(1) << 20);
}

TEST_F(InputFileTest, BadLimitIsAnError) {
  for (const char* bad : {"abc", "0", "-5", "12MB", "99999999999999999999"}) {
    const InputLimit limit(bad);
    EXPECT_THROW(input_limit_bytes(), std::invalid_argument) << bad;
  }
  unsetenv("PERIFRAC_MAX_INPUT_MB");
  EXPECT_EQ(input_limit_bytes(), size_t(1024) << 20);
}

// The same rules by metadata alone, for files a library opens itself; a checkpoint-style read
// takes a file of any size but stops at the size it had.
TEST_F(InputFileTest, MetadataCheckAndOwnFilesFollowTheSameRules) {
  std::string why;
  std::ofstream(path("sky.hdr")) << "#?RADIANCE\n";
  EXPECT_TRUE(is_bounded_input(path("sky.hdr"), why)) << why;
  EXPECT_FALSE(is_bounded_input("/dev/zero", why));
  EXPECT_NE(why.find("not a regular file"), std::string::npos) << why;
  {
    const InputLimit limit("1");
    std::ofstream(path("big.hdr")) << std::string(size_t(1) << 21, 'x');
    EXPECT_FALSE(is_bounded_input(path("big.hdr"), why));
    EXPECT_NE(why.find("larger than the input limit"), std::string::npos) << why;
    const std::optional<std::string> own = read_output_file(path("big.hdr"), why);
    ASSERT_TRUE(own) << why;
    EXPECT_EQ(own->size(), size_t(1) << 21);
  }
  EXPECT_FALSE(read_output_file("/dev/urandom", why));
}

}  // namespace
}  // namespace pd
