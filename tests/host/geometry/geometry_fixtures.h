// Helpers of the geometry tests: a scratch directory, the shared test meshes (skipped when
// absent) and small text files.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pd::test {

// A fresh directory under the system temp folder, removed at the end of the test.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("perifrac-geom-" + name + "-" +
               std::to_string(::testing::UnitTest::GetInstance()->random_seed()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A mesh of the project's shared folder (never copied into the repository); empty when absent.
inline std::string shared_mesh(const std::string& name) {
  const std::string path = PERIFRAC_SOURCE_DIR "/../shared/data/meshes/" + name;
  return std::filesystem::exists(path) ? path : std::string();
}

}  // namespace pd::test

// Skips the test with a message when a shared mesh is absent (a user's clone has no shared/).
#define PD_REQUIRE_SHARED_MESH(var, name)                \
  const std::string var = ::pd::test::shared_mesh(name); \
  if (var.empty())                                       \
  GTEST_SKIP() << "shared mesh " << name                 \
               << " not found at " PERIFRAC_SOURCE_DIR "/../shared/data/meshes/ (test skipped)"
