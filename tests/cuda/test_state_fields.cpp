// The state table (cuda/state_fields.h): every saved field survives a checkpoint file and an
// engine save / restore bit for bit, the views carry the lengths the table gives, and a view
// index out of range stops the run with a message where bounds checks are compiled in.
#include "cuda/state_fields.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/app/checkpoint.h"
#include "tests/support/fixtures.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

// The bytes of a vector, for comparisons that hold for any element type.
template <class T>
std::string bytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// Fills every field of a snapshot with `count` elements of distinct bytes (seeded per field).
void fill_distinct(EngineSnapshot& s, size_t count) {
  unsigned char seed = 1;
  for_each_snapshot_field(s, [&](const char*, auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    v.resize(count);
    std::vector<unsigned char> raw(count * sizeof(T));
    for (size_t k = 0; k < raw.size(); ++k) raw[k] = static_cast<unsigned char>(seed * 31 + k * 7);
    std::memcpy(static_cast<void*>(v.data()), raw.data(), raw.size());
    ++seed;
  });
}

class StateFieldsFile : public testing::TempDirTest {};

TEST_F(StateFieldsFile, EverySavedFieldSurvivesTheCheckpointFile) {
  RunCheckpoint c;
  c.scene_path = "scene.toml";
  c.backend = "cpu";
  fill_distinct(c.engine, 5);
  c.steps_per_frame = 10;  // (a checkpoint after frame 0: step 0 to 10)
  c.engine.step = 3;
  int fields = 0;
  for_each_snapshot_field(c.engine, [&](const char*, const auto&) { ++fields; });
  EXPECT_GE(fields, 9);  // disp, vel, force, strain_min, intact, ledger, state, neighbor, plastic
  write_checkpoint(path("c.pfc"), c);
  RunCheckpoint back = read_checkpoint(path("c.pfc"));
  // Pairs the fields of the two snapshots by name, in the table's order.
  std::vector<std::pair<std::string, std::string>> written, read;
  for_each_snapshot_field(c.engine, [&](const char* name, const auto& v) {
    written.push_back({name, bytes(v)});
  });
  for_each_snapshot_field(back.engine, [&](const char* name, const auto& v) {
    read.push_back({name, bytes(v)});
  });
  ASSERT_EQ(written.size(), read.size());
  for (size_t k = 0; k < written.size(); ++k) {
    EXPECT_EQ(written[k].first, read[k].first);
    EXPECT_EQ(written[k].second, read[k].second) << "field " << written[k].first << " did not survive";
  }
}

// A plastic state-based block pulled apart across a weakened plane: every field of the table
// exists (state, plastic history, strength) and changes.
SimulationInput busy_block() {
  SimulationInput in = testing::pulled_apart(testing::state_block(8, 4, 4, 1e-3, 2e-3, true), 8, 1e-3, 6.0);
  testing::weaken_plane(in, 4e-3, 0.5);
  return in;
}

TEST(StateFieldsEngine, SaveRestoreSaveGivesTheSameBitsForEveryField) {
  const SimulationInput in = busy_block();
  auto engine = make_cpu_engine(in);
  engine->advance(40);
  EXPECT_GT(engine->broken_bonds(), 0);
  EngineSnapshot first;
  engine->save(first);
  for_each_snapshot_field(first, [&](const char* name, const auto& v) {
    EXPECT_FALSE(v.empty()) << "field " << name << " is empty in a run that has every feature";
  });
  auto other = make_cpu_engine(in);
  other->restore(first);
  EngineSnapshot second;
  other->save(second);
  std::vector<std::string> a, b;
  for_each_snapshot_field(first, [&](const char*, const auto& v) { a.push_back(bytes(v)); });
  for_each_snapshot_field(second, [&](const char*, const auto& v) { b.push_back(bytes(v)); });
  EXPECT_EQ(a, b);
  // And the restored engine runs on as the original does.
  engine->advance(20);
  other->advance(20);
  EngineSnapshot x, y;
  engine->save(x);
  other->save(y);
  a.clear();
  b.clear();
  for_each_snapshot_field(x, [&](const char*, const auto& v) { a.push_back(bytes(v)); });
  for_each_snapshot_field(y, [&](const char*, const auto& v) { b.push_back(bytes(v)); });
  EXPECT_EQ(a, b);
}

TEST(StateFieldsEngine, FieldsARunDoesNotHaveAreEmpty) {
  auto engine = make_cpu_engine(testing::lattice_block(4, 4, 4, 1e-3));
  EngineSnapshot s;
  engine->save(s);
  EXPECT_EQ(s.disp.size(), 64u);
  EXPECT_TRUE(s.state.empty());
  EXPECT_TRUE(s.plastic.empty());
  // A frame reads back the fields with a frame role: the displacement's xyz, velocity, force and
  // intact bonds, one per particle.
  ParticleState frame;
  engine->read_state(frame);
  EXPECT_EQ(frame.disp.size(), 64u);
  EXPECT_EQ(frame.vel.size(), 64u);
  EXPECT_EQ(frame.force.size(), 64u);
  ASSERT_EQ(frame.intact.size(), 64u);
  for (size_t i = 0; i < 64; ++i) {
    EXPECT_EQ(frame.disp[i].x, s.disp[i].x);
    EXPECT_EQ(frame.intact[i], s.intact[i]);
  }
}

TEST(StateFields, BytesPerParticleAndSlotFollowTheTable) {
  // rest, disp, state 16; vel, force 12; ledger 16; inv_mass, strain_limit0, strain_min, intact,
  // body, count 4; material 2; flags, anchor 1.
  EXPECT_EQ(field_bytes<kParticles>(FieldNeeds{}), 16 * 2 + 12 * 2 + 16 + 4 * 6 + 2 + 1 * 2);
  EXPECT_EQ(field_bytes<kParticles>(FieldNeeds{true, false, false}),
            field_bytes<kParticles>(FieldNeeds{}) + 16);
  EXPECT_EQ(field_bytes<kSlots>(FieldNeeds{}), 4);
  EXPECT_EQ(field_bytes<kSlots>(FieldNeeds{true, true, false}), 12);
  EXPECT_EQ(field_bytes<kSlots>(FieldNeeds{false, false, true}), 5);
}

TEST(ArrayViewBounds, AnIndexOutOfRangeStopsWithAMessage) {
#if defined(PERIFRAC_BOUNDS_CHECKS)
  std::vector<real> values(3, real(1));
  const ArrayView<real> v = view_of(values);
  EXPECT_EQ(v[2], real(1));
  EXPECT_DEATH((void)v[3], "index 3 out of \\[0, 3\\)");
  EXPECT_DEATH((void)v[-1], "index -1 out of \\[0, 3\\)");
#else
  GTEST_SKIP() << "bounds checks are compiled in by PERIFRAC_BOUNDS_CHECKS (the cpu-asan preset)";
#endif
}

}  // namespace
}  // namespace pd
