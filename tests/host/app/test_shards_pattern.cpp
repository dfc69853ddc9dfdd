// [[shards]] patterns (host/app/shards_pattern.h): a first run's broken bonds become the faces of
// a second, its dust grouped into cells; the checks that the first run is of this scene.
#include "host/app/shards_pattern.h"

#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <string>

#include "cuda/engine/bond_cuts.h"
#include "cuda/engine/engine.h"
#include "cuda/parallel/partition.h"
#include "host/app/checkpoint.h"
#include "host/fragments/components.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

// A small glass plate punched by a projectile: it cracks and sheds dust within 150 steps.
const std::string kPlate = R"(
[simulation]
dt = "auto"
seed = 3
[materials.glass]
density = 2440
bulk_modulus = 4e10
strain_limit = 1e-3
compression_alpha = 0.25
[[bodies]]
name = "plate"
size = [0.04, 0.04, 0.006]
spacing = 0.002
material = "glass"
[[projectiles]]
center = [0.0, 0.0, 0.012]
velocity = [0.0, 0.0, -150.0]
radius = 0.008
strength = 1e8
)";

constexpr int64_t kSteps = 150;

class ShardsPattern : public testing::TempDirTest {
 protected:
  // Runs the plate (no pattern) and writes its checkpoint to first/; returns its bonds.
  BondLists first_run(double scale = 1.0) {
    const Scene scene = parse_scene(kPlate, path("scene.toml"));
    const SetupResult setup = setup_scene_with_patterns(scene, scale, Backend::kCpu);
    const auto engine = make_engine(Backend::kCpu, setup.input);
    engine->advance(kSteps);
    RunCheckpoint c;
    c.scale = scale;
    c.setup_hash = setup_fingerprint(setup.input);
    c.scene_path = path("scene.toml");
    c.steps_per_frame = kSteps;
    c.frames = 1;
    c.frame = 1;
    c.backend = "cpu";
    engine->save(c.engine);
    std::filesystem::create_directories(path("first"));
    write_checkpoint(path("first/") + kCheckpointFileName, c);
    BondLists bonds;
    engine->read_bonds(bonds);
    return bonds;
  }
  Scene second_scene(const std::string& extra = "size = 0.004\nhold = 10\n") const {
    return parse_scene(kPlate + "[[shards]]\npattern = \"first\"\n" + extra, path("scene.toml"));
  }
};

// The faces are the first run's broken bonds less those inside one dust cell; every limit of the
// body and its compression strengthening are raised by the hold; the dust is the first run's
// pieces of fewer than 8 particles.
TEST_F(ShardsPattern, FacesAreTheFirstRunsBrokenBondsAndTheRestHolds) {
  const BondLists first = first_run();
  const Scene plain_scene = parse_scene(kPlate, path("scene.toml"));
  const SetupResult plain = setup_scene_with_patterns(plain_scene, 1.0, Backend::kCpu);
  const SetupResult second = setup_scene_with_patterns(second_scene(), 1.0, Backend::kCpu);
  const ParticleSet& ps = second.input.particles;
  const BondsView v = first.view();
  std::set<uint64_t> broken;
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k)
      if (!bond_intact(v.neighbor[v.slot(i, k)]))
        broken.insert(bond_key(i, bond_partner(v.neighbor[v.slot(i, k)])));
  ASSERT_GT(broken.size(), 100u) << "the first run should break bonds";

  // Faces: a subset of the broken bonds, sorted and unique, and every broken bond left out joins
  // two dust particles (of one cell).
  const auto& faces = second.input.face_bonds;
  ASSERT_FALSE(faces.empty());
  EXPECT_TRUE(std::is_sorted(faces.begin(), faces.end()));
  EXPECT_EQ(std::adjacent_find(faces.begin(), faces.end()), faces.end());
  Components pieces;
  ComponentFinder(plain.adjacency, first).find(first, pieces);
  auto dust = [&](int32_t i) {
    return pieces.size(size_t(pieces.index[size_t(i)])) < kPatternPieceParticles;
  };
  int64_t dust_particles = 0;
  for (size_t i = 0; i < ps.size(); ++i) dust_particles += dust(int32_t(i));
  EXPECT_GT(dust_particles, 0) << "the first run should leave dust";
  EXPECT_EQ(second.pattern.dust, dust_particles);
  EXPECT_GT(second.pattern.cells, 0);
  EXPECT_EQ(second.pattern.faces, int64_t(faces.size()));
  EXPECT_EQ(second.pattern.bodies, 1);
  const std::set<uint64_t> face_set(faces.begin(), faces.end());
  int64_t left_out = 0;
  for (const uint64_t key : broken) {
    if (face_set.count(key)) continue;
    ++left_out;
    EXPECT_TRUE(dust(int32_t(key >> 32)) && dust(int32_t(key & 0xffffffffu))) << key;
  }
  for (const uint64_t key : faces) EXPECT_EQ(broken.count(key), 1u) << key;
  EXPECT_GT(left_out, 0) << "bonds inside dust cells hold";

  // Limits and compression strengthening raised by 255/26 (hold 10); strengths 26.
  ASSERT_EQ(ps.shard_strength.size(), ps.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    EXPECT_EQ(ps.shard_strength[i], 26);
    EXPECT_EQ(ps.shard[i], -1);
    EXPECT_NEAR(ps.strain_limit0[i], plain.input.particles.strain_limit0[i] * 255.0 / 26, 1e-9);
  }
  EXPECT_NEAR(second.input.materials.m[0].compression_alpha, 0.25 * 255 / 26, 1e-5);

  // The engine weakens exactly the faces, from both ends.
  const auto engine = make_engine(Backend::kCpu, second.input);
  EXPECT_EQ(engine->family_stats().cuts.weakened, 2 * int64_t(faces.size()));
}

// The second run breaks along the first run's cracks: nearly every bond it breaks is a face, and
// most faces open again.
TEST_F(ShardsPattern, SecondRunBreaksAlongTheFirstRunsCracks) {
  first_run();
  const SetupResult second = setup_scene_with_patterns(second_scene(), 1.0, Backend::kCpu);
  const auto engine = make_engine(Backend::kCpu, second.input);
  engine->advance(kSteps);
  BondLists bonds;
  engine->read_bonds(bonds);
  const std::set<uint64_t> faces(second.input.face_bonds.begin(), second.input.face_bonds.end());
  const BondsView v = bonds.view();
  int64_t broken = 0, on_faces = 0;
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k)
      if (!bond_intact(v.neighbor[v.slot(i, k)])) {
        ++broken;
        on_faces += faces.count(bond_key(i, bond_partner(v.neighbor[v.slot(i, k)])));
      }
  // Measured: 61,178 slots broken, 61,132 of them faces (the projectile crushes a few bonds
  // that hold 10 times the limit); 94% of the faces' slots open again.
  EXPECT_GE(double(on_faces), 0.99 * double(broken));
  EXPECT_GE(double(on_faces), 0.8 * 2 * double(faces.size()));
}

// dust_hold: the dust's cells hold by their own factor, on a copy of the material entry whose
// compression strengthening is raised by it; the rest of the body keeps `hold`.
TEST_F(ShardsPattern, DustHoldsByItsOwnFactor) {
  first_run();
  const SetupResult plain =
      setup_scene_with_patterns(parse_scene(kPlate, path("scene.toml")), 1.0, Backend::kCpu);
  const SetupResult ten = setup_scene_with_patterns(second_scene(), 1.0, Backend::kCpu);
  const SetupResult two =
      setup_scene_with_patterns(second_scene("size = 0.004\nhold = 10\ndust_hold = 2\n"), 1.0, Backend::kCpu);
  const ParticleSet& ps = two.input.particles;
  ASSERT_EQ(ps.shard_strength.size(), ps.size());
  EXPECT_EQ(two.pattern.dust, ten.pattern.dust);
  EXPECT_EQ(two.input.face_bonds, ten.input.face_bonds);  // the same faces: the same cells
  ASSERT_EQ(two.pattern.dust_materials.size(), 1u);
  EXPECT_EQ(two.pattern.dust_materials[0], (std::pair<uint16_t, uint16_t>(0, 1)));
  ASSERT_EQ(two.input.materials.count, 2);
  EXPECT_NEAR(two.input.materials.m[0].compression_alpha, 0.25 * 255 / 26, 1e-5);
  EXPECT_NEAR(two.input.materials.m[1].compression_alpha, 0.25 * 255 / 128, 1e-5);
  ASSERT_EQ(two.materials.size(), 2u);
  EXPECT_EQ(two.materials[1].body, "plate (shards dust)");
  int64_t dust = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const bool is_dust = ps.material[i] == 1;
    dust += is_dust;
    EXPECT_EQ(ps.shard_strength[i], is_dust ? 128 : 26) << i;
    EXPECT_NEAR(ps.strain_limit0[i], plain.input.particles.strain_limit0[i] * 255.0 / (is_dust ? 128 : 26),
                1e-9);
  }
  EXPECT_EQ(dust, two.pattern.dust);

  // Weaker dust cells give way more: more bonds inside the dust's cells (not faces) break.
  auto inside_breaks = [&](const SetupResult& s) {
    const auto engine = make_engine(Backend::kCpu, s.input);
    engine->advance(kSteps);
    BondLists bonds;
    engine->read_bonds(bonds);
    const std::set<uint64_t> faces(s.input.face_bonds.begin(), s.input.face_bonds.end());
    const BondsView v = bonds.view();
    int64_t n = 0;
    for (int32_t i = 0; i < v.n; ++i)
      for (int32_t k = 0; k < v.count[i]; ++k) {
        const int32_t nb = v.neighbor[v.slot(i, k)];
        n += !bond_intact(nb) && s.input.particles.material[size_t(i)] == 1 &&
             s.input.particles.material[size_t(bond_partner(nb))] == 1 &&
             !faces.count(bond_key(i, bond_partner(nb)));
      }
    return n;
  };
  // (`ten` has no dust entry: its dust is told by the same particles as `two`'s.)
  SetupResult ten_marked = ten;
  for (size_t i = 0; i < ps.size(); ++i) ten_marked.input.particles.material[i] = ps.material[i];
  ten_marked.input.materials = two.input.materials;
  ten_marked.input.materials.m[1] = ten.input.materials.m[0];
  const int64_t at_two = inside_breaks(two), at_ten = inside_breaks(ten_marked);
  EXPECT_GT(at_two, at_ten) << "dust_hold 2: " << at_two << ", 10: " << at_ten;
}

TEST_F(ShardsPattern, TheLoaderRefusesDustHoldWithoutAPattern) {
  try {
    parse_scene(kPlate + "[[shards]]\nsize = 0.004\ndust_hold = 2\n", path("scene.toml"));
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("shards[0].dust_hold"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("together with pattern"), std::string::npos) << e.what();
  }
}

void expect_pattern_error(const std::function<void()>& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("shards[0].pattern"), std::string::npos) << what;
    EXPECT_NE(what.find(part), std::string::npos) << what;
  }
}

TEST_F(ShardsPattern, AFolderWithoutACheckpointIsNamed) {
  expect_pattern_error([&] { setup_scene_with_patterns(second_scene(), 1.0, Backend::kCpu); },
                       "--checkpoint-every");
}

TEST_F(ShardsPattern, AnotherScaleIsRefused) {
  first_run(1.0);
  expect_pattern_error([&] { setup_scene_with_patterns(second_scene(), 0.5, Backend::kCpu); }, "--scale");
}

TEST_F(ShardsPattern, AnotherSceneIsRefused) {
  first_run();
  // Another strain limit: the same particles, other limits.
  const Scene other =
      parse_scene(kPlate + "[[shards]]\npattern = \"first\"\nsize = 0.004\n" +
                      "[[regions]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.01\n"
                      "strain_limit_factor = 2\n",
                  path("scene.toml"));
  expect_pattern_error([&] { setup_scene_with_patterns(other, 1.0, Backend::kCpu); }, "other particles");
}

TEST_F(ShardsPattern, TheLoaderRefusesAPatternWithAZone) {
  for (const std::string& extra : {std::string("size = 0.004\nradius = 0.01\ncenter = [0.0, 0.0, 0.0]\n")}) {
    try {
      second_scene(extra);
      ADD_FAILURE() << "accepted";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("a pattern over the whole body, or a zone"), std::string::npos)
          << e.what();
    }
  }
  try {
    parse_scene(kPlate + "[[shards]]\npattern = \"\"\nsize = 0.004\n", path("scene.toml"));
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("shards[0].pattern"), std::string::npos) << e.what();
  }
}

// Ranks: the faces whose two ends a rank holds, at its local indices.
TEST(LocalFaceBonds, KeepsThePairsARankHoldsAtLocalIndices) {
  RankLayout layout;
  layout.global = {5, 2, 9};  // local 0, 1, 2
  const std::vector<uint64_t> faces = {bond_key(2, 5), bond_key(2, 9), bond_key(5, 7), bond_key(0, 1)};
  const std::vector<uint64_t> local = local_face_bonds(faces, layout, 10);
  EXPECT_EQ(local, (std::vector<uint64_t>{bond_key(0, 1), bond_key(1, 2)}));
  EXPECT_TRUE(local_face_bonds({}, layout, 10).empty());
}

}  // namespace
}  // namespace pd
