// Shards ([[shards]], host/scene/scene_shards.h): the seeds' grid and nearest-seed search, the
// cells, strengths and strain limits setup_scene gives a body, and the loader's messages.
#include "host/scene/scene_shards.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "host/geometry/random.h"
#include "host/scene/scene_setup.h"

namespace pd {
namespace {

const std::string kTwoPlates = R"(
[simulation]
seed = 5
[materials.glass]
density = 2440
bulk_modulus = 4e10
strain_limit = 1e-3
strain_limit_scatter = 0
compression_alpha = 0.25
[[bodies]]
name = "plate"
size = [0.02, 0.01, 0.004]
spacing = 0.001
material = "glass"
[[bodies]]
name = "other"
center = [0.0, 0.05, 0.0]
size = [0.01, 0.01, 0.004]
spacing = 0.001
material = "glass"
)";

TEST(SceneShards, NearestIsTheNearestSeedOfAll) {
  const ShardSeeds s = shard_seeds({0, 0, 0}, {0.1, 0.05, 0.02}, 0.01, 1.0, 3);
  EXPECT_EQ(s.n[0], 10);
  EXPECT_EQ(s.n[1], 5);
  EXPECT_EQ(s.n[2], 2);
  Random rng(11);
  for (int t = 0; t < 2000; ++t) {
    const std::array<double, 3> x = {0.1 * rng.uniform(), 0.05 * rng.uniform(), 0.02 * rng.uniform()};
    int64_t brute = 0;
    double best = 1e300;
    for (size_t k = 0; k < s.seed.size(); ++k) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a)
        d2 += (x[size_t(a)] - s.seed[k][size_t(a)]) * (x[size_t(a)] - s.seed[k][size_t(a)]);
      if (d2 < best) {
        best = d2;
        brute = int64_t(k);
      }
    }
    ASSERT_EQ(s.nearest(x), brute) << t;
  }
}

TEST(SceneShards, NoJitterIsACubicGrid) {
  const ShardSeeds s = shard_seeds({0, 0, 0}, {0.03, 0.02, 0.01}, 0.01, 0.0, 3);
  ASSERT_EQ(s.seed.size(), 6u);
  EXPECT_DOUBLE_EQ(s.seed[0][0], 0.005);
  EXPECT_DOUBLE_EQ(s.seed[5][0], 0.025);
  EXPECT_DOUBLE_EQ(s.seed[5][1], 0.015);
  EXPECT_EQ(s.nearest({0.012, 0.001, 0.002}), 1);
}

TEST(SceneShards, SetupGivesTheNamedBodyCellsStrengthsAndLimits) {
  const auto setup = [] {
    return setup_scene(
        parse_scene(kTwoPlates + "[[shards]]\nsize = 0.005\nhold = 4\nbody = \"plate\"\n", "scene.toml"),
        SetupOptions(1.0));
  };
  const SetupResult r = setup();
  const ParticleSet& ps = r.input.particles;
  ASSERT_EQ(ps.shard.size(), ps.size());
  ASSERT_EQ(ps.shard_strength.size(), ps.size());
  std::map<int32_t, int> per_cell;
  for (size_t i = 0; i < ps.size(); ++i) {
    if (ps.body[i] == 0) {
      EXPECT_GE(ps.shard[i], 0);
      EXPECT_EQ(ps.shard_strength[i], 64);  // 255 / 4, rounded
      // Raised by 255 / 64, so that a bond between cells (64 / 255 of it) keeps exactly 1e-3.
      EXPECT_NEAR(ps.strain_limit0[i], 255.0 / 64 * 1e-3, 1e-9);
      ++per_cell[ps.shard[i]];
    } else {
      EXPECT_EQ(ps.shard[i], -1);
      EXPECT_NEAR(ps.strain_limit0[i], 1e-3, 1e-9);
    }
  }
  // The plate's compression strengthening raised as its limits (its own material table entry).
  EXPECT_NEAR(r.input.materials.m[ps.material[0]].compression_alpha, 255.0 / 64 * 0.25, 1e-6);
  EXPECT_NEAR(r.input.materials.m[ps.material.back()].compression_alpha, 0.25, 1e-7);
  // A 20 x 10 x 4 mm plate in cells of 5 mm: 4 x 2 x 1 grid cells, every one holding particles.
  EXPECT_EQ(r.shards.cells, 8);
  EXPECT_EQ(int64_t(per_cell.size()), r.shards.cells);
  EXPECT_EQ(r.shards.particles, 20 * 10 * 4);
  // The same scene again: the same cells (the seeds come from simulation.seed).
  const SetupResult again = setup();
  EXPECT_EQ(again.input.particles.shard, ps.shard);
}

TEST(SceneShards, ATableWithoutBodyCoversEveryBodyWithCellsOfTheirOwn) {
  const SetupResult r =
      setup_scene(parse_scene(kTwoPlates + "[[shards]]\nsize = 0.005\n", "scene.toml"), SetupOptions(1.0));
  const ParticleSet& ps = r.input.particles;
  std::set<int32_t> cells[2];
  for (size_t i = 0; i < ps.size(); ++i) {
    ASSERT_GE(ps.shard[i], 0);
    EXPECT_EQ(ps.shard_strength[i], 85);  // hold 3 by default
    cells[ps.body[i]].insert(ps.shard[i]);
  }
  for (int32_t c : cells[1]) EXPECT_EQ(cells[0].count(c), 0u) << "a cell shared by two bodies";
  EXPECT_EQ(r.shards.cells, int64_t(cells[0].size() + cells[1].size()));
}

// A zone: only the plate's particles within 4 mm of its centre get cells, on a copy of the
// plate's material entry with its compression strengthening raised; the rest keep the material.
TEST(SceneShards, AZoneHoldsOnlyTheParticlesWithinItsRadius) {
  const SetupResult r = setup_scene(
      parse_scene(kTwoPlates + "[[shards]]\nsize = 0.002\nhold = 4\nbody = \"plate\"\nradius = 0.004\n"
                               "center = [0.0, 0.0, 0.0]\n",
                  "scene.toml"),
      SetupOptions(1.0));
  const ParticleSet& ps = r.input.particles;
  ASSERT_EQ(r.input.materials.count, 3);  // plate, other, the plate's zone
  ASSERT_EQ(r.materials.size(), 3u);
  EXPECT_EQ(r.materials[2].body, "plate (shards zone)");
  ASSERT_EQ(r.shards.zone_materials.size(), 1u);
  EXPECT_EQ(r.shards.zone_materials[0], (std::pair<uint16_t, uint16_t>(0, 2)));
  int64_t inside = 0, outside = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const double r2 = double(ps.rest[i].x) * ps.rest[i].x + double(ps.rest[i].y) * ps.rest[i].y +
                      double(ps.rest[i].z) * ps.rest[i].z;
    if (ps.body[i] == 0 && r2 <= 0.004 * 0.004) {
      ++inside;
      EXPECT_GE(ps.shard[i], 0);
      EXPECT_EQ(ps.shard_strength[i], 64);
      EXPECT_EQ(ps.material[i], 2);
      EXPECT_NEAR(ps.strain_limit0[i], 255.0 / 64 * 1e-3, 1e-9);
    } else {
      outside += ps.body[i] == 0;
      EXPECT_EQ(ps.shard[i], -1);
      EXPECT_EQ(ps.shard_strength[i], 255);
      EXPECT_EQ(ps.material[i], ps.body[i]);
      EXPECT_NEAR(ps.strain_limit0[i], 1e-3, 1e-9);
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 400);
  EXPECT_EQ(r.shards.particles, inside);
  EXPECT_NEAR(r.input.materials.m[2].compression_alpha, 255.0 / 64 * 0.25, 1e-6);
  EXPECT_NEAR(r.input.materials.m[0].compression_alpha, 0.25, 1e-7);
  EXPECT_EQ(r.input.materials.m[2].bulk_modulus, r.input.materials.m[0].bulk_modulus);
  // A zone over the whole body needs no copy: the body's entry is raised in place.
  const SetupResult whole = setup_scene(
      parse_scene(kTwoPlates + "[[shards]]\nsize = 0.002\nhold = 4\nbody = \"plate\"\nradius = 1\n"
                               "center = [0.0, 0.0, 0.0]\n",
                  "scene.toml"),
      SetupOptions(1.0));
  EXPECT_EQ(whole.input.materials.count, 2);
  EXPECT_TRUE(whole.shards.zone_materials.empty());
}

TEST(SceneShards, NoTableNoFields) {
  const SetupResult r = setup_scene(parse_scene(kTwoPlates, "scene.toml"), SetupOptions(1.0));
  EXPECT_TRUE(r.input.particles.shard.empty());
  EXPECT_TRUE(r.input.particles.shard_strength.empty());
  EXPECT_EQ(r.shards.cells, 0);
}

void expect_scene_error(const std::string& extra, const std::string& key, const std::string& allowed) {
  try {
    parse_scene(kTwoPlates + extra, "scene.toml");
    ADD_FAILURE() << "accepted: " << extra;
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene.toml"), std::string::npos) << what;
    EXPECT_NE(what.find(key), std::string::npos) << what;
    EXPECT_NE(what.find(allowed), std::string::npos) << what;
  }
}

TEST(SceneShards, BadTablesAreNamed) {
  expect_scene_error("[[shards]]\nhold = 3\n", "shards[0].size", "required");
  expect_scene_error("[[shards]]\nsize = 0\n", "shards[0].size", "> 0");
  expect_scene_error("[[shards]]\nsize = 0.01\nhold = 1\n", "shards[0].hold", "(1, 255]");
  expect_scene_error("[[shards]]\nsize = 0.01\nhold = 300\n", "shards[0].hold", "255");
  expect_scene_error("[[shards]]\nsize = 0.01\njitter = 2\n", "shards[0].jitter", "[0, 1]");
  expect_scene_error("[[shards]]\nsize = 0.01\nbody = \"vase\"\n", "shards[0].body", "plate");
  expect_scene_error("[[shards]]\nsize = 0.01\nbody = \"plate\"\n[[shards]]\nsize = 0.02\nbody = \"plate\"\n",
                     "shards[1].body", "one [[shards]] per body");
  expect_scene_error("[[shards]]\nsize = 0.01\n[[shards]]\nsize = 0.02\nbody = \"other\"\n", "shards[1].body",
                     "one [[shards]] per body");
  expect_scene_error("[[shards]]\nsize = 0.01\nhole = 3\n", "hole", "hold");
  expect_scene_error("[[shards]]\nsize = 0.01\nradius = 0\n", "shards[0].radius", "> 0");
  expect_scene_error("[[shards]]\nsize = 0.01\nradius = 0.01\n", "shards[0].center", "required");
  expect_scene_error("[[shards]]\nsize = 0.01\ncenter = [0, 0, 0]\n", "shards[0].center", "with radius");
}

TEST(SceneShards, TooManyCellsIsAClearError) {
  try {
    setup_scene(parse_scene(kTwoPlates + "[[shards]]\nsize = 1e-6\n", "scene.toml"), SetupOptions(1.0));
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("shards[0].size"), std::string::npos) << what;
    EXPECT_NE(what.find("a larger size"), std::string::npos) << what;
  }
}

// More zones than the material table holds: one clear message naming the zone's radius.
TEST(SceneShards, ZonesBeyondTheMaterialTableAreAClearError) {
  std::string scene = kTwoPlates;
  for (int b = 2; b < kMaxMaterials; ++b)
    scene += "[[bodies]]\nname = \"b" + std::to_string(b) + "\"\ncenter = [0.0, " + std::to_string(0.05 * b) +
             ", 0.0]\nsize = [0.004, 0.004, 0.004]\nspacing = 0.001\nmaterial = \"glass\"\n";
  scene += "[[shards]]\nsize = 0.002\nbody = \"plate\"\nradius = 0.004\ncenter = [0.0, 0.0, 0.0]\n";
  try {
    setup_scene(parse_scene(scene, "scene.toml"), SetupOptions(1.0));
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("shards[0].radius"), std::string::npos) << what;
    EXPECT_NE(what.find("at most 16 bodies, shards zones and dust holds"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace pd
