#include "host/io/atomic_file.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using AtomicFileTest = pd::testing::TempDirTest;
using pd::testing::expect_io_error;
using pd::testing::read_all;

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

// A full disk: a 64 KiB tmpfs mounted in the test folder (root only; the test skips where the
// system refuses the mount). The write fails with ENOSPC naming the path, the old file stays and
// no temporary is left behind.
TEST_F(AtomicFileTest, DiskFullIsReportedWithThePath) {
  const std::string dir = path("full");
  fs::create_directories(dir);
  if (mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here (" << std::strerror(errno) << "): needs root";
  const std::string target = dir + "/out.txt";
  pd::write_file_atomic(target, std::string_view("old"));
  expect_io_error([&] { pd::write_file_atomic(target, std::string(1 << 20, 'x')); }, target,
                  "No space left on device");
  EXPECT_EQ(read_all(target), "old");
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
  umount2(dir.c_str(), MNT_DETACH);
}

// A folder the user may not write to: the error names the path and the reason. Root may write
// anywhere, so as root the write runs in a child process that has dropped to an ordinary user.
TEST_F(AtomicFileTest, PermissionDeniedIsReportedWithThePath) {
  const std::string dir = path("locked");
  fs::create_directories(dir);
  chmod(dir.c_str(), 0555);
  const std::string target = dir + "/out.txt";
  auto attempt = [&]() -> int {
    try {
      pd::write_file_atomic(target, std::string_view("data"));
    } catch (const pd::IoError& e) {
      const std::string m = e.what();
      return m.find(target) != std::string::npos && m.find("Permission denied") != std::string::npos ? 0 : 1;
    }
    return 2;
  };
  if (geteuid() != 0) {
    EXPECT_EQ(attempt(), 0);
  } else {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0)
      _exit(setresgid(65534, 65534, 65534) == 0 && setresuid(65534, 65534, 65534) == 0 ? attempt() : 3);
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0)
        << "1: message without the path or reason, 2: no error, 3: setuid failed";
  }
  EXPECT_FALSE(fs::exists(target));
  chmod(dir.c_str(), 0755);
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

// Temporaries of killed writers are removed; the live process's own and other files stay.
TEST_F(AtomicFileTest, StaleTemporariesOfDeadWritersAreRemoved) {
  const std::string dead = path("frame_00001.pfr.tmp.2147483646.0");
  const std::string live = path("frame_00002.pfr.tmp." + std::to_string(getpid()) + ".0");
  for (const std::string& p : {dead, live, path("frame_00001.pfr"), path("notes.tmp.txt")})
    pd::write_file_atomic(p, std::string_view("x"));
  EXPECT_EQ(pd::remove_stale_temporaries(dir_.string()), 1u);
  EXPECT_FALSE(std::filesystem::exists(dead));
  EXPECT_TRUE(std::filesystem::exists(live));
  EXPECT_TRUE(std::filesystem::exists(path("frame_00001.pfr")));
  EXPECT_TRUE(std::filesystem::exists(path("notes.tmp.txt")));
}

}  // namespace
