// TetGen's meshes kept between runs (host/geometry/tet_cache.h): an entry gives back the mesh it
// was given, only for the same input, never when it is not whole; the folder keeps its bound; a
// second tetrahedralization of the same surface takes the cached tets.
#include "host/geometry/tet_cache.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "host/geometry/shapes.h"
#include "host/geometry/tetgen.h"
#include "tests/host/geometry/geometry_fixtures.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

// Two tets sharing a face, as TetGen would list them.
TetMesh two_tets(double shift) {
  TetMesh m;
  m.vertices = {{shift, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.neighbors = {{1, -1, -1, -1}, {-1, -1, -1, 0}};
  return m;
}

void expect_same(const TetMesh& a, const TetMesh& b) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.neighbors, b.neighbors);
}

// Sets an environment variable for one test, restoring it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    value ? setenv(name, value, 1) : unsetenv(name);
  }
  ~ScopedEnv() { had_ ? setenv(name_, old_.c_str(), 1) : unsetenv(name_); }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

TEST(TetCache, GivesBackTheMeshOfTheSameInputOnly) {
  test::ScratchDir dir("tetcache-same");
  const TetMesh mesh = two_tets(0.25);
  EXPECT_FALSE(TetCache(dir.file("c"), "input a").load());  // nothing kept yet
  TetCache(dir.file("c"), "input a").store(mesh);
  const std::optional<TetMesh> kept = TetCache(dir.file("c"), "input a").load();
  ASSERT_TRUE(kept);
  expect_same(*kept, mesh);
  EXPECT_FALSE(TetCache(dir.file("c"), "input b").load());
}

// An entry cut short, or with a byte changed, is no entry; storing again mends it.
TEST(TetCache, IgnoresAnEntryThatIsNotWhole) {
  test::ScratchDir dir("tetcache-whole");
  const TetCache cache(dir.file("c"), "input");
  cache.store(two_tets(0.25));
  const uintmax_t size = fs::file_size(cache.path());
  fs::resize_file(cache.path(), size - 1);
  EXPECT_FALSE(cache.load());
  cache.store(two_tets(0.25));
  {
    std::fstream f(cache.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(size - 20));
    f.put('\x7f');
  }
  EXPECT_FALSE(cache.load());
  {
    std::ofstream(cache.path(), std::ios::binary) << "PFTETS01";  // a header cut short
  }
  EXPECT_FALSE(cache.load());
  cache.store(two_tets(0.25));
  ASSERT_TRUE(cache.load());
  expect_same(*cache.load(), two_tets(0.25));
}

// With room for two entries, a third removes the one used longest ago.
TEST(TetCache, KeepsItsFolderWithinItsBound) {
  test::ScratchDir dir("tetcache-bound");
  const TetMesh mesh = two_tets(0.25);
  TetCache(dir.file("c"), "first").store(mesh);
  const uint64_t entry = fs::file_size(TetCache(dir.file("c"), "first").path());
  const uint64_t bound = 2 * entry + entry / 2;
  const auto later = [](const std::string& path, int seconds) {
    fs::last_write_time(path, fs::file_time_type::clock::now() + std::chrono::seconds(seconds));
  };
  TetCache(dir.file("c"), "second", bound).store(mesh);
  later(TetCache(dir.file("c"), "second").path(), 10);
  ASSERT_TRUE(TetCache(dir.file("c"), "first").load());  // used now: "second" stays newer (+10 s)
  later(TetCache(dir.file("c"), "first").path(), 20);    // ... and now "first" is the newer one
  TetCache(dir.file("c"), "third", bound).store(mesh);
  EXPECT_TRUE(fs::exists(TetCache(dir.file("c"), "first").path()));
  EXPECT_FALSE(fs::exists(TetCache(dir.file("c"), "second").path()));
  EXPECT_TRUE(fs::exists(TetCache(dir.file("c"), "third").path()));
}

TEST(TetCache, FolderComesFromTheEnvironment) {
  {
    ScopedEnv cache("PERIFRAC_TET_CACHE", "off");
    EXPECT_EQ(tet_cache_folder(), "");
  }
  ScopedEnv cache("PERIFRAC_TET_CACHE", nullptr);
  {
    ScopedEnv xdg("XDG_CACHE_HOME", "/somewhere");
    EXPECT_EQ(tet_cache_folder(), "/somewhere/perifrac/tets");
  }
  ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
  {
    ScopedEnv home("HOME", "/home/artist");
    EXPECT_EQ(tet_cache_folder(), "/home/artist/.cache/perifrac/tets");
    ScopedEnv given("PERIFRAC_TET_CACHE", "/fast/disk");
    EXPECT_EQ(tet_cache_folder(), "/fast/disk");
  }
  ScopedEnv home("HOME", nullptr);
  EXPECT_EQ(tet_cache_folder(), "");
}

// The same surface tetrahedralized twice: the second time from the cache, the same tets.
TEST(TetCache, TheSecondTetrahedralizationTakesTheCachedTets) {
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  test::ScratchDir dir("tetcache-twice");
  ScopedEnv cache("PERIFRAC_TET_CACHE", dir.file("c").c_str());
  const TriMesh sphere = sphere_mesh(1, 0.2);
  std::vector<StageTime> first, second;
  TetgenOptions options;
  options.max_volume = 0.01;
  options.stages = &first;
  const TetMesh made = tetrahedralize(sphere, options, "sphere");
  options.stages = &second;
  const TetMesh kept = tetrahedralize(sphere, options, "sphere");
  expect_same(kept, made);
  ASSERT_FALSE(second.empty());
  EXPECT_EQ(second.back().name, "tets from the cache");
  EXPECT_NE(first.back().name, "tets from the cache");
  options.max_volume = 0.02;  // other switches: TetGen again
  options.stages = &second;
  second.clear();
  tetrahedralize(sphere, options, "sphere");
  EXPECT_EQ(second.back().name, "tetgen output files");
}

// A cache folder that cannot be written: one warning, and the tets all the same.
TEST(TetCache, AFolderThatCannotBeWrittenLeavesTheTetsAsTetGenMadeThem) {
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed";
  ScopedEnv cache("PERIFRAC_TET_CACHE", "/proc/perifrac-tets");
  TetgenOptions options;
  options.max_volume = 0.01;
  ::testing::internal::CaptureStderr();
  const TetMesh mesh = tetrahedralize(sphere_mesh(1, 0.2), options, "sphere");
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_GT(mesh.tets.size(), 100u);
  EXPECT_FALSE(fs::exists("/proc/perifrac-tets"));
  // (Said once per process; no other test fails to write a cache.)
  EXPECT_NE(said.find("set PERIFRAC_TET_CACHE to another folder, or to off"), std::string::npos) << said;
}

}  // namespace
}  // namespace pd
