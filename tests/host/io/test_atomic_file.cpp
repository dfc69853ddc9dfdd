#include "host/io/atomic_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// A fresh, empty directory per test, removed afterwards.
class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) / ("perifrac_" + std::string(info->test_suite_name()) + "_" +
                                             info->name() + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Names of the entries in the test directory, sorted.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `f`, expecting an IoError whose message names `path` and contains `reason`.
template <class F>
void expect_io_error(F&& f, const std::string& path, const std::string& reason) {
  try {
    f();
    ADD_FAILURE() << "no IoError for " << path;
  } catch (const pd::IoError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("'" + path + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

// Lowers the file size limit for its lifetime, so that writes past it fail with EFBIG
// (SIGXFSZ, which would kill the process, is ignored meanwhile).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_handler_ = signal(SIGXFSZ, SIG_IGN);
    rlimit lowered = saved_;
    lowered.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &lowered);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit saved_;
  void (*previous_handler_)(int);
};

TEST_F(AtomicFileTest, WritesBytesAndReplacesAnExistingTarget) {
  std::string target = path("out.txt");
  pd::write_file_atomic(target, std::string_view("old contents"));
  EXPECT_EQ(read_all(target), "old contents");
  pd::write_file_atomic(target, std::string_view("new"));
  EXPECT_EQ(read_all(target), "new");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, StreamWritesOfEverySizeArriveInOrder) {
  // Mix single characters, small writes and writes larger than the internal buffer.
  std::string expected;
  for (size_t size : {1, 7, 1000, 65535, 65536, 65537, 200000, 3}) {
    expected += std::string(size, char('a' + size % 26));
  }
  std::string target = path("big.bin");
  pd::write_file_atomic(target, [&](std::ostream& out) {
    out.put(expected[0]);
    size_t at = 1;
    for (size_t size : {6, 1000, 65535, 65536, 65537, 200000, 3}) {
      out.write(expected.data() + at, std::streamsize(size));
      at += size;
    }
    out << expected.substr(at);
  });
  EXPECT_EQ(read_all(target), expected);
}

TEST_F(AtomicFileTest, WritesThroughATemporaryBesideTheTarget) {
  std::string target = path("frame.vtu");
  std::vector<std::string> during;
  pd::write_file_atomic(target, [&](std::ostream& out) {
    out << "data";
    during = entries();
  });
  ASSERT_EQ(during.size(), 1u);
  EXPECT_EQ(during[0].rfind("frame.vtu", 0), 0u) << during[0];
  EXPECT_NE(during[0].find(".tmp"), std::string::npos) << during[0];
  EXPECT_EQ(entries(), std::vector<std::string>{"frame.vtu"});
}

TEST_F(AtomicFileTest, NewFilesGetTheUsualPermissions) {
  mode_t mask = umask(022);
  umask(mask);
  std::string target = path("perm.txt");
  pd::write_file_atomic(target, std::string_view("x"));
  struct stat st;
  ASSERT_EQ(stat(target.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0666 & ~mask);
}

TEST_F(AtomicFileTest, MissingDirectoryThrowsNamingThePath) {
  std::string target = path("missing/out.txt");
  expect_io_error([&] { pd::write_file_atomic(target, std::string_view("x")); }, target,
                  "No such file or directory");
  EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicFileTest, ParentThatIsARegularFileThrows) {
  pd::write_file_atomic(path("plain"), std::string_view("a file"));
  std::string target = path("plain/out.txt");
  expect_io_error([&] { pd::write_file_atomic(target, std::string_view("x")); }, target, "Not a directory");
  EXPECT_EQ(entries(), std::vector<std::string>{"plain"});
  EXPECT_EQ(read_all(path("plain")), "a file");
}

TEST_F(AtomicFileTest, TargetThatIsADirectoryFailsAtRenameAndCleansUp) {
  fs::create_directory(path("sub"));
  expect_io_error([&] { pd::write_file_atomic(path("sub"), std::string_view("x")); }, path("sub"),
                  "Is a directory");
  EXPECT_EQ(entries(), std::vector<std::string>{"sub"});
}

TEST_F(AtomicFileTest, ExceptionFromTheWriterKeepsTheOldTarget) {
  std::string target = path("out.txt");
  pd::write_file_atomic(target, std::string_view("old"));
  auto throwing = [](std::ostream& out) {
    out << std::string(100000, 'x');
    throw std::logic_error("writer gave up");
  };
  EXPECT_THROW(pd::write_file_atomic(target, throwing), std::logic_error);
  EXPECT_EQ(read_all(target), "old");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, StreamLeftFailedByTheWriterThrowsIoError) {
  std::string target = path("out.txt");
  pd::write_file_atomic(target, std::string_view("old"));
  auto failing = [](std::ostream& out) {
    out << "partial";
    out.setstate(std::ios::badbit);
  };
  expect_io_error([&] { pd::write_file_atomic(target, failing); }, target, "output stream failed");
  EXPECT_EQ(read_all(target), "old");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, OsWriteErrorIsReportedWithItsReason) {
  std::string target = path("out.txt");
  pd::write_file_atomic(target, std::string_view("old"));
  std::string big(1 << 20, 'x');
  {
    FileSizeLimit limit(64 * 1024);
    expect_io_error([&] { pd::write_file_atomic(target, big); }, target, "File too large");
  }
  EXPECT_EQ(read_all(target), "old");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, EnsureDirectoryCreatesParentsAndAcceptsExisting) {
  std::string nested = path("a/b/c");
  pd::ensure_directory(nested);
  EXPECT_TRUE(fs::is_directory(nested));
  pd::ensure_directory(nested);
  pd::ensure_directory(path("a/b/c/"));
  EXPECT_TRUE(fs::is_directory(nested));
}

TEST_F(AtomicFileTest, EnsureDirectoryBelowARegularFileThrows) {
  pd::write_file_atomic(path("plain"), std::string_view("a file"));
  std::string nested = path("plain/sub");
  expect_io_error([&] { pd::ensure_directory(nested); }, nested, "cannot create directory");
  expect_io_error([&] { pd::ensure_directory(path("plain")); }, path("plain"), "cannot create directory");
  EXPECT_EQ(read_all(path("plain")), "a file");
}

}  // namespace
