// Checkpoint files: exact round trip, and corrupted, truncated, foreign and other-version files
// refused with a message naming the path and the problem.
#include "host/app/checkpoint.h"

#include <gtest/gtest.h>

#include "host/io/atomic_file.h"
#include "host/io/frame_file.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

RunCheckpoint sample() {
  RunCheckpoint c;
  c.scene_path = "scenes/a b.toml";
  c.scene_hash = 0x0123456789abcdefull;
  c.setup_hash = 42;
  c.scale = 0.1;  // not exact in binary: must come back bit for bit
  c.steps_per_frame = 200;
  c.frames = 30;
  c.blend_frames = 3;
  c.allow_unstable_dt = true;
  c.backend = "cpu";
  c.frame = 7;
  c.engine.step = 1400;
  c.engine.time = 1.0 / 3.0;
  c.engine.disp = {{1, 2, 3, 4}, {5, 6, 7, 8}};
  c.engine.vel = {{0.1f, 0.2f, 0.3f}, {-1, -2, -3}};
  c.engine.force = {{9, 8, 7}, {6, 5, 4}};
  c.engine.strain_min = {-1e-3f, 2e-3f};
  c.engine.intact = {3, 4};
  c.engine.ledger = {{1.5, 2.5}, {3.5, 4.5}};
  c.engine.neighbor = {1, ~0, 0, 1, 0, 0, 0};
  c.energy0.kinetic = 12.5;
  c.energy0.work = -1e-9;
  c.energy_log = "frame,step\n0,0\n";
  c.series = {{0.0, "frame_00000.vtu"}, {1e-4 / 3, "frame_00001.vtu"}};
  c.smoother.previous_index = {0, 0};
  FragmentSmoother::Correction k;
  k.particles = 2;
  k.rotation = Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5);
  k.offset = Eigen::Vector3d(1e-3, 0, -2);
  k.age = 1;
  c.smoother.previous = {k};
  return c;
}

using testing::read_all;

class Checkpoint : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    path_ = path("checkpoint.pck");
  }
  // Expects reading path_ to fail with a message naming it and containing `what`.
  void expect_refused(const std::string& what) {
    testing::expect_io_error([&] { read_checkpoint(path_); }, path_, what);
  }
  std::string path_;
};

TEST_F(Checkpoint, RoundTripIsExact) {
  const RunCheckpoint a = sample();
  write_checkpoint(path_, a);
  const RunCheckpoint b = read_checkpoint(path_);
  EXPECT_EQ(b.scene_path, a.scene_path);
  EXPECT_EQ(b.scene_hash, a.scene_hash);
  EXPECT_EQ(b.setup_hash, a.setup_hash);
  EXPECT_EQ(b.scale, a.scale);
  EXPECT_EQ(b.engine.time, a.engine.time);
  EXPECT_EQ(b.engine.step, a.engine.step);
  EXPECT_EQ(b.frame, a.frame);
  EXPECT_EQ(b.blend_frames, a.blend_frames);
  EXPECT_TRUE(b.allow_unstable_dt);
  EXPECT_EQ(b.backend, "cpu");
  ASSERT_EQ(b.engine.disp.size(), 2u);
  EXPECT_EQ(b.engine.disp[1].w, 8);
  EXPECT_EQ(b.engine.vel[0].y, 0.2f);
  EXPECT_EQ(b.engine.ledger[1].released, 4.5);
  EXPECT_EQ(b.engine.neighbor, a.engine.neighbor);
  EXPECT_TRUE(b.engine.state.empty());
  EXPECT_TRUE(b.engine.plastic.empty());
  EXPECT_EQ(b.energy0.kinetic, 12.5);
  EXPECT_EQ(b.energy0.work, -1e-9);
  EXPECT_EQ(b.energy_log, a.energy_log);
  ASSERT_EQ(b.series.size(), 2u);
  EXPECT_EQ(b.series[1].time, a.series[1].time);
  EXPECT_EQ(b.series[1].file, "frame_00001.vtu");
  ASSERT_EQ(b.smoother.previous.size(), 1u);
  EXPECT_EQ(b.smoother.previous[0].rotation.coeffs(), a.smoother.previous[0].rotation.coeffs());
  EXPECT_EQ(b.smoother.previous[0].offset, a.smoother.previous[0].offset);
  EXPECT_EQ(b.smoother.previous[0].age, 1);
}

TEST_F(Checkpoint, CorruptedByteIsRefused) {
  write_checkpoint(path_, sample());
  std::string bytes = read_all(path_);
  bytes[bytes.size() / 2] ^= 0x10;
  write_file_atomic(path_, bytes);
  expect_refused("checksum mismatch");
}

TEST_F(Checkpoint, TruncatedFileIsRefused) {
  write_checkpoint(path_, sample());
  const std::string bytes = read_all(path_);
  for (size_t keep : {size_t(0), size_t(5), size_t(20), bytes.size() / 2, bytes.size() - 1}) {
    write_file_atomic(path_, std::string_view(bytes).substr(0, keep));
    expect_refused(keep < 20 ? "truncated" : "checksum mismatch");
  }
}

TEST_F(Checkpoint, ForeignFileIsRefused) {
  FrameData f;
  f.position = {{0, 0, 0}};
  f.velocity = {{0, 0, 0}};
  f.damage = {0};
  f.body = {0};
  write_frame_file(path_, f);
  expect_refused("not a perifrac checkpoint");
}

TEST_F(Checkpoint, OtherVersionIsRefused) {
  write_checkpoint(path_, sample());
  std::string bytes = read_all(path_);
  bytes[8] = char(kCheckpointVersion + 1);  // the version follows the 8-byte magic
  write_file_atomic(path_, bytes);
  expect_refused("format version");
}

TEST_F(Checkpoint, MissingFileIsReported) {
  expect_refused("No such file");
}

// Engines restore what they saved; a snapshot of another size is refused without change.
TEST(EngineSnapshot, RestoreRefusesOtherSizes) {
  SimulationInput in;
  // Two particles 1 mm apart, bonded.
  in.materials.count = 1;
  in.materials.m[0].horizon = real(3e-3);
  in.materials.m[0].spacing = real(1e-3);
  in.materials.m[0].micromodulus = real(1e15);
  in.particles.add({0, 0, 0}, {0, 0, 0}, real(1e-9), real(1e-6), real(1e-2), 0, 0);
  in.particles.add({1e-3f, 0, 0}, {1, 0, 0}, real(1e-9), real(1e-6), real(1e-2), 0, 0);
  in.step.dt = real(1e-7);
  auto engine = make_cpu_engine(in);
  engine->advance(3);
  EngineSnapshot s;
  engine->save(s);
  auto other = make_cpu_engine(in);
  other->restore(s);
  EXPECT_EQ(other->step(), 3);
  other->advance(2);
  engine->advance(2);
  ParticleState a, b;
  engine->read_state(a);
  other->read_state(b);
  EXPECT_EQ(a.disp[1].x, b.disp[1].x);
  EXPECT_EQ(a.vel[0].x, b.vel[0].x);
  s.vel.pop_back();
  EXPECT_THROW(other->restore(s), std::invalid_argument);
  EXPECT_EQ(other->step(), 5);
}

}  // namespace
}  // namespace pd
