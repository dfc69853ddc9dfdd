#include "host/io/frame_file.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <limits>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "host/io/atomic_file.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

namespace {

using FrameFileTest = pd::testing::TempDirTest;
using pd::testing::expect_io_error;
using pd::testing::read_all;

// Plain (non-atomic, no fsync) write, for the many corrupted inputs the tests make.
void write_bytes(const std::string& path, std::string_view bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}

template <class T>
void poke(std::string& bytes, size_t offset, T value) {
  std::memcpy(&bytes[offset], &value, sizeof value);
}

template <class T>
T peek(const std::string& bytes, size_t offset) {
  T value;
  std::memcpy(&value, &bytes[offset], sizeof value);
  return value;
}

// Byte offsets of the header fields (docs/output-formats.md).
constexpr size_t kVersionAt = 8, kKindAt = 12, kCountAt = 16, kFrameAt = 24, kStepAt = 32, kTimeAt = 40,
                 kArrayCountAt = 48, kFirstArrayAt = 52, kArrayHeaderBytes = 24;

pd::FrameData sample_frame() {
  pd::FrameData f;
  f.frame = 42;
  f.step = 123456789012;
  f.time = 1.0 / 3.0;
  f.position = {{0.1, -0.2, 0.3}, {1e-3, 2.5, -7}, {-1.1, 1e-7, 3.3}};
  f.velocity = {{1, 2, 3}, {-0.1, 0.2, -0.3}, {1e3, -1e-3, 0.7}};
  f.damage = {0.f, 0.3f, 1.f};
  f.body = {0, 1, -1};
  f.component = {4, 4, 9};
  return f;
}

pd::RestData sample_rest() {
  pd::RestData r;
  r.position = {{0.1, 0.2, 0.3}, {-4, 5e-5, 6.6}};
  r.volume = {1e-9f, 2.5e-9f};
  r.body = {0, 3};
  r.material = {1, 0};
  return r;
}

// Positions and velocities come back rounded to float32.
void expect_float32_equal(const std::vector<pd::Vec3>& got, const std::vector<pd::Vec3>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].x, pd::real(float(want[i].x))) << i;
    EXPECT_EQ(got[i].y, pd::real(float(want[i].y))) << i;
    EXPECT_EQ(got[i].z, pd::real(float(want[i].z))) << i;
  }
}

// Offset of array `index` in a file of `n` particles whose arrays have these component counts.
size_t array_offset(size_t n, const std::vector<size_t>& components, size_t index) {
  size_t at = kFirstArrayAt;
  for (size_t i = 0; i < index; ++i) at += kArrayHeaderBytes + n * components[i] * 4;
  return at;
}

const std::vector<size_t> kFrameComponents = {3, 3, 1, 1, 1};  // position velocity damage body component

TEST_F(FrameFileTest, FrameRoundTrips) {
  pd::FrameData f = sample_frame();
  std::string file = path(pd::frame_file_name(f.frame, "pfr"));
  EXPECT_EQ(file, path("frame_00042.pfr"));
  pd::write_frame_file(file, f);
  pd::FrameData g = pd::read_frame_file(file);
  EXPECT_EQ(g.frame, f.frame);
  EXPECT_EQ(g.step, f.step);
  EXPECT_EQ(g.time, f.time);
  expect_float32_equal(g.position, f.position);
  expect_float32_equal(g.velocity, f.velocity);
  EXPECT_EQ(g.damage, f.damage);
  EXPECT_EQ(g.body, f.body);
  EXPECT_EQ(g.component, f.component);
}

TEST_F(FrameFileTest, EmptyComponentIsLeftOutAndReadsBackEmpty) {
  pd::FrameData f = sample_frame();
  f.component.clear();
  pd::write_frame_file(path("f.pfr"), f);
  std::string bytes = read_all(path("f.pfr"));
  EXPECT_EQ(peek<uint32_t>(bytes, kArrayCountAt), 4u);
  EXPECT_EQ(bytes.size(), array_offset(3, kFrameComponents, 4));
  pd::FrameData g = pd::read_frame_file(path("f.pfr"));
  EXPECT_TRUE(g.component.empty());
  EXPECT_EQ(g.body, f.body);
}

TEST_F(FrameFileTest, RestRoundTrips) {
  pd::RestData r = sample_rest();
  pd::write_rest_file(path(pd::kRestFileName), r);
  pd::RestData s = pd::read_rest_file(path("rest.pfr"));
  expect_float32_equal(s.position, r.position);
  EXPECT_EQ(s.volume, r.volume);
  EXPECT_EQ(s.body, r.body);
  EXPECT_EQ(s.material, r.material);
}

TEST_F(FrameFileTest, ZeroParticlesRoundTrip) {
  pd::FrameData f;
  f.frame = 1;
  pd::write_frame_file(path("f.pfr"), f);
  pd::FrameData g = pd::read_frame_file(path("f.pfr"));
  EXPECT_EQ(g.frame, 1);
  EXPECT_TRUE(g.position.empty());
  EXPECT_TRUE(g.damage.empty());
}

TEST_F(FrameFileTest, ByteLayoutMatchesTheDocumentation) {
  pd::FrameData f = sample_frame();
  pd::write_frame_file(path("f.pfr"), f);
  std::string b = read_all(path("f.pfr"));
  ASSERT_EQ(b.size(), array_offset(3, kFrameComponents, 5));
  EXPECT_EQ(b.substr(0, 8), std::string("PFRAME\0\0", 8));
  EXPECT_EQ(peek<uint32_t>(b, kVersionAt), 1u);
  EXPECT_EQ(peek<uint32_t>(b, kKindAt), 1u);
  EXPECT_EQ(peek<uint64_t>(b, kCountAt), 3u);
  EXPECT_EQ(peek<int64_t>(b, kFrameAt), 42);
  EXPECT_EQ(peek<int64_t>(b, kStepAt), 123456789012);
  EXPECT_EQ(peek<double>(b, kTimeAt), 1.0 / 3.0);
  EXPECT_EQ(peek<uint32_t>(b, kArrayCountAt), 5u);

  const char* names[] = {"position", "velocity", "damage", "body", "component"};
  const uint32_t types[] = {pd::kPfrFloat32, pd::kPfrFloat32, pd::kPfrFloat32, pd::kPfrInt32, pd::kPfrInt32};
  for (size_t i = 0; i < 5; ++i) {
    size_t at = array_offset(3, kFrameComponents, i);
    std::string name = b.substr(at, 16);
    EXPECT_EQ(name, std::string(names[i]) + std::string(16 - std::strlen(names[i]), '\0'));
    EXPECT_EQ(peek<uint32_t>(b, at + 16), types[i]) << names[i];
    EXPECT_EQ(peek<uint32_t>(b, at + 20), kFrameComponents[i]) << names[i];
  }
  EXPECT_EQ(peek<float>(b, kFirstArrayAt + kArrayHeaderBytes + 4), float(f.position[0].y));
}

TEST_F(FrameFileTest, EveryTruncationIsRefused) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string bytes = read_all(path("f.pfr"));
  for (size_t length = 0; length < bytes.size(); ++length) {
    std::string cut = path("cut.pfr");
    write_bytes(cut, std::string_view(bytes).substr(0, length));
    expect_io_error([&] { pd::read_frame_file(cut); }, cut, "truncated");
  }
}

// A number that is not finite (a damaged file: a run writes none) is refused, not drawn.
TEST_F(FrameFileTest, NumbersThatAreNotFiniteAreRefused) {
  pd::FrameData f = sample_frame();
  f.velocity[0].y = std::numeric_limits<pd::real>::infinity();
  pd::write_frame_file(path("frame.pfr"), f);
  EXPECT_THROW(pd::read_frame_file(path("frame.pfr")), pd::IoError);
  pd::RestData r = sample_rest();
  r.position[1].z = std::numeric_limits<pd::real>::quiet_NaN();
  pd::write_rest_file(path("rest.pfr"), r);
  EXPECT_THROW(pd::read_rest_file(path("rest.pfr")), pd::IoError);
}

TEST_F(FrameFileTest, WrongMagicIsRefused) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string bytes = read_all(path("f.pfr"));
  bytes[1] = 'X';
  write_bytes(path("f.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("f.pfr")); }, path("f.pfr"), "wrong magic");
  write_bytes(path("text.pfr"), std::string_view("<?xml version=\"1.0\"?> and a lot more text here"));
  expect_io_error([&] { pd::read_frame_file(path("text.pfr")); }, path("text.pfr"), "wrong magic");
}

TEST_F(FrameFileTest, ForeignKindIsRefused) {
  pd::write_frame_file(path("frame.pfr"), sample_frame());
  pd::write_rest_file(path("rest.pfr"), sample_rest());
  expect_io_error([&] { pd::read_frame_file(path("rest.pfr")); }, path("rest.pfr"),
                  "is a rest file, expected a frame file");
  expect_io_error([&] { pd::read_rest_file(path("frame.pfr")); }, path("frame.pfr"),
                  "is a frame file, expected a rest file");
}

TEST_F(FrameFileTest, UnknownVersionAndKindAreRefused) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string good = read_all(path("f.pfr"));
  std::string bytes = good;
  poke<uint32_t>(bytes, kVersionAt, 2);
  write_bytes(path("v2.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("v2.pfr")); }, path("v2.pfr"), "unknown version 2");
  bytes = good;
  poke<uint32_t>(bytes, kKindAt, 7);
  write_bytes(path("k7.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("k7.pfr")); }, path("k7.pfr"), "unknown kind 7");
}

TEST_F(FrameFileTest, HugeParticleCountIsRefusedWithoutAllocating) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string bytes = read_all(path("f.pfr"));
  for (uint64_t count : {uint64_t(1) << 62, ~uint64_t(0), uint64_t(1) << 30}) {
    poke<uint64_t>(bytes, kCountAt, count);
    write_bytes(path("huge.pfr"), bytes);
    expect_io_error([&] { pd::read_frame_file(path("huge.pfr")); }, path("huge.pfr"), "truncated");
  }
  // One particle too many: the arrays no longer line up with the file, whatever fails first.
  poke<uint64_t>(bytes, kCountAt, 4);
  write_bytes(path("off.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("off.pfr")); }, path("off.pfr"), "cannot read");
}

TEST_F(FrameFileTest, ArrayOfTheWrongTypeIsRefused) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string bytes = read_all(path("f.pfr"));
  poke<uint32_t>(bytes, array_offset(3, kFrameComponents, 1) + 16, pd::kPfrInt32);
  write_bytes(path("f.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("f.pfr")); }, path("f.pfr"),
                  "array 'velocity' is int32 x3, expected float32 x3");
}

TEST_F(FrameFileTest, MissingRequiredArrayIsRefused) {
  pd::FrameData f = sample_frame();
  f.component.clear();
  pd::write_frame_file(path("f.pfr"), f);
  std::string bytes = read_all(path("f.pfr"));
  bytes.resize(array_offset(3, kFrameComponents, 3));  // drop `body`
  poke<uint32_t>(bytes, kArrayCountAt, 3);
  write_bytes(path("f.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("f.pfr")); }, path("f.pfr"), "missing array 'body'");
}

TEST_F(FrameFileTest, DuplicateArrayAndTrailingBytesAreRefused) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string good = read_all(path("f.pfr"));
  std::string bytes = good;
  std::memcpy(&bytes[array_offset(3, kFrameComponents, 4)], "body\0\0\0\0\0\0\0\0\0\0\0\0", 16);
  write_bytes(path("dup.pfr"), bytes);
  expect_io_error([&] { pd::read_frame_file(path("dup.pfr")); }, path("dup.pfr"),
                  "array 'body' appears twice");
  write_bytes(path("tail.pfr"), good + "junk");
  expect_io_error([&] { pd::read_frame_file(path("tail.pfr")); }, path("tail.pfr"),
                  "4 unexpected bytes after the last array");
}

TEST_F(FrameFileTest, UnknownArraysAreSkipped) {
  pd::FrameData f = sample_frame();
  pd::write_frame_file(path("f.pfr"), f);
  std::string bytes = read_all(path("f.pfr"));
  std::memcpy(&bytes[array_offset(3, kFrameComponents, 4)], "stress_future\0\0\0", 16);
  write_bytes(path("f.pfr"), bytes);
  pd::FrameData g = pd::read_frame_file(path("f.pfr"));
  EXPECT_TRUE(g.component.empty());
  EXPECT_EQ(g.body, f.body);
}

TEST_F(FrameFileTest, MissingFileNamesThePathAndReason) {
  expect_io_error([&] { pd::read_frame_file(path("none.pfr")); }, path("none.pfr"),
                  "No such file or directory");
  expect_io_error([&] { pd::read_rest_file(dir_.string()); }, dir_.string(), "not a regular file");
}

TEST_F(FrameFileTest, RandomCorruptionIsRefusedOrReadNeverCrashes) {
  pd::write_frame_file(path("f.pfr"), sample_frame());
  std::string good = read_all(path("f.pfr"));
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 500; ++trial) {
    std::string bytes = good;
    int flips = 1 + int(rng() % 4);
    for (int i = 0; i < flips; ++i) {
      // Half the flips hit the header and first array header, where sizes live.
      size_t at = rng() % 2 ? rng() % (kFirstArrayAt + kArrayHeaderBytes) : rng() % bytes.size();
      bytes[at] = char(rng());
    }
    write_bytes(path("bad.pfr"), bytes);
    try {
      pd::read_frame_file(path("bad.pfr"));
    } catch (const pd::IoError&) {
    }
  }
}

TEST_F(FrameFileTest, FailedWriteThrowsAndLeavesNothing) {
  std::string target = path("missing/frame_00001.pfr");
  expect_io_error([&] { pd::write_frame_file(target, sample_frame()); }, target, "No such file or directory");
  write_bytes(path("plain"), std::string_view("x"));
  expect_io_error([&] { pd::write_rest_file(path("plain/rest.pfr"), sample_rest()); }, path("plain/rest.pfr"),
                  "Not a directory");
  EXPECT_EQ(entry_count(), 1u);
}

TEST_F(FrameFileTest, InconsistentSizesAreRejected) {
  pd::FrameData f = sample_frame();
  f.velocity.pop_back();
  EXPECT_THROW(pd::write_frame_file(path("f.pfr"), f), std::invalid_argument);
  pd::RestData r = sample_rest();
  r.material.clear();
  EXPECT_THROW(pd::write_rest_file(path("r.pfr"), r), std::invalid_argument);
  EXPECT_EQ(entry_count(), 0u);
}

}  // namespace
