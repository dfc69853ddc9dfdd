// Fuzzing regressions: every input that once crashed, hung or broke the contract of a fuzz target
// (tests/fuzz/regressions/<target>/) goes through the same entry as the target, and must give a
// valid result or a clean error. The seed corpus must give valid results. docs/fuzzing.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_entries.h"
#include "tests/fuzz/fuzz_run_entries.h"

namespace pd {
namespace {

namespace fs = std::filesystem;
using Entry = std::function<std::string(const std::string&)>;

const fs::path kFuzzDir = fs::path(PERIFRAC_SOURCE_DIR) / "tests" / "fuzz";

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// The files of one folder, sorted by name (none when it does not exist).
std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir))
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// The entry of each fuzz target, by the target's folder name.
Entry entry_of(const std::string& target) {
  if (target == "scene") return fuzz::scene_entry;
  if (target == "checkpoint") return fuzz::checkpoint_entry;
  if (target == "command_line") return fuzz::command_line_entry;
  const fuzz::MeshFormat format = target == "obj"   ? fuzz::MeshFormat::obj
                                  : target == "ply" ? fuzz::MeshFormat::ply
                                                    : fuzz::MeshFormat::stl;
  return [format](const std::string& bytes) { return fuzz::mesh_entry(format, bytes); };
}

// Every regression input of `target` ends in a valid result or a clean error; a broken contract
// (fuzz::ContractViolation) or any other exception fails the test with the file's name.
void expect_regressions_pass(const std::string& target) {
  const Entry entry = entry_of(target);
  for (const fs::path& file : files_in(kFuzzDir / "regressions" / target)) {
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(entry(read_bytes(file)));
  }
}

TEST(FuzzRegressions, Scene) {
  expect_regressions_pass("scene");
}
TEST(FuzzRegressions, Obj) {
  expect_regressions_pass("obj");
}
TEST(FuzzRegressions, Ply) {
  expect_regressions_pass("ply");
}
TEST(FuzzRegressions, Stl) {
  expect_regressions_pass("stl");
}
TEST(FuzzRegressions, Checkpoint) {
  expect_regressions_pass("checkpoint");
}
TEST(FuzzRegressions, CommandLine) {
  expect_regressions_pass("command_line");
}

// The seeds are valid inputs, so that fuzzing starts from files that reach the checks after parsing.
TEST(FuzzCorpus, EverySeedIsValid) {
  for (const std::string target : {"scene", "obj", "ply", "stl", "checkpoint", "command_line"}) {
    const Entry entry = entry_of(target);
    const std::vector<fs::path> seeds = files_in(kFuzzDir / "corpus" / target);
    EXPECT_GE(seeds.size(), 4u) << target;
    for (const fs::path& seed : seeds) EXPECT_EQ(entry(read_bytes(seed)), "") << seed;
  }
}

// toml++ 3.3 reached __builtin_unreachable() when it asked whether characters such as U+0488 or
// U+00A7 are whitespace: outside a string, and after a line-ending backslash in a multi-line one.
TEST(FuzzRegressions, TomlCharactersThatBreakTheWhitespaceTable) {
  EXPECT_EQ(fuzz::scene_entry("[materials\xd2\x88.plastic]\n"),
            "fuzz/input.toml:1:11: TOML syntax error: Error while parsing table header: expected ']', "
            "saw '\xd2\x88'");
  // The same characters in strings and keys read back unchanged (upstream issue #190's example).
  const Scene scene = parse_scene(
      "description = \"\"\"\\\n\xc2\xa7 bris\xc3\xa9\"\"\"\n"
      "[materials.\"\xc3\xa9\"]\ndensity = 1.0\nbulk_modulus = 1.0\nstrain_limit = 0.01\n"
      "[[bodies]]\nsize = [1, 1, 1]\nspacing = 0.1\nmaterial = \"\xc3\xa9\" # \xc3\xa9\n",
      "unicode.toml");
  EXPECT_EQ(scene.description, "\xc2\xa7 bris\xc3\xa9");
  EXPECT_EQ(scene.materials[0].name, "\xc3\xa9");
  EXPECT_EQ(scene.bodies[0].material, "\xc3\xa9");
  // A private-use character that stands in for another while parsing is refused.
  EXPECT_NE(fuzz::scene_entry("description = \"\xf3\xb0\x83\xa9 \xc3\xa9\"\n").find("private-use"),
            std::string::npos);
}

// An STL corner (NaN, 1, 0) was welded to the vertex (0, 1, 0), and the NaN file passed as a solid.
TEST(FuzzRegressions, StlNanCornerIsReported) {
  const std::string error =
      fuzz::mesh_entry(fuzz::MeshFormat::stl,
                       read_bytes(kFuzzDir / "regressions" / "stl" / "nan_corner_welded_to_a_vertex.stl"));
  EXPECT_NE(error.find("not a finite number"), std::string::npos) << error;
}

// A huge direction was normalised through an overflowing length to [0, 0, 0]: an isotropic G.
TEST(FuzzRegressions, AnisotropyDirectionIsNormalisedWithoutOverflow) {
  const std::string scene =
      "[materials.s]\nmodel = \"state_based\"\ndensity = 1.0\nbulk_modulus = 1.0\nshear_modulus = 1.0\n"
      "strain_limit = 0.01\n[materials.s.anisotropy]\ndirection = [D, D, 0]\nratio = 2\n"
      "[[bodies]]\nsize = [1, 1, 1]\nspacing = 0.1\nmaterial = \"s\"\n";
  auto matrix = [&](const std::string& component) {
    std::string text = scene;
    for (size_t at; (at = text.find('D')) != std::string::npos;) text.replace(at, 1, component);
    return parse_scene(text, "aniso.toml").materials[0].anisotropy->matrix;
  };
  const auto unit = matrix("1.0"), huge = matrix("1e200"), tiny = matrix("1e-200");
  for (int k = 0; k < 9; ++k) {
    EXPECT_NEAR(huge[k], unit[k], 1e-15) << k;
    EXPECT_NEAR(tiny[k], unit[k], 1e-15) << k;
  }
  EXPECT_NEAR(unit[0], 0.75, 1e-15);  // 1 + (1/2 - 1) / 2
}

}  // namespace
}  // namespace pd
