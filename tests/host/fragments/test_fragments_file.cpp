// The fragments file: round trip, byte layout of the header and a record, refused bad files.
#include "host/fragments/fragments_file.h"

#include <gtest/gtest.h>

#include <limits>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/geometry/random.h"
#include "host/io/atomic_file.h"
#include "tests/host/fragments/fragment_fixtures.h"

namespace pd {
namespace {

using FragmentsFileTest = testing::TempDirTest;

std::vector<Fragment> random_fragments(size_t n, uint64_t seed) {
  Random rng(seed);
  auto vec = [&] { return Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal()); };
  auto rot = [&] {
    return Eigen::Quaterniond(rng.normal(), rng.normal(), rng.normal(), rng.normal())
        .normalized()
        .toRotationMatrix();
  };
  std::vector<Fragment> out(n);
  for (size_t k = 0; k < n; ++k) {
    Fragment& f = out[k];
    f.id = int32_t(7 * k);
    f.particles = int32_t(1 + k);
    f.fit.mass = rng.uniform();
    f.fit.rest_centroid = vec();
    f.fit.centroid = vec();
    f.fit.rotation = rot();
    f.fit.translation = vec();
    f.fit.rms = rng.uniform();
    f.fit.radius = 1 + rng.uniform();
    f.rotation = k % 2 ? rot() : f.fit.rotation;
    f.translation = vec();
    f.blend = k % 2 ? rng.uniform() : 0;
  }
  return out;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(FragmentsFileTest, RoundTrip) {
  for (size_t n : {0, 1, 5, 1000}) {
    const std::vector<Fragment> f = random_fragments(n, n + 1);
    const std::string p = path(fragments_file_name(42));
    write_fragments_file(p, 42, 4200, 1.25e-3, f);
    const FragmentsFrame back = read_fragments_file(p);
    EXPECT_EQ(back.frame, 42);
    EXPECT_EQ(back.step, 4200);
    EXPECT_EQ(back.time, 1.25e-3);
    ASSERT_EQ(back.fragments.size(), n);
    for (size_t k = 0; k < n; ++k) {
      const Fragment &a = f[k], &b = back.fragments[k];
      EXPECT_EQ(a.id, b.id);
      EXPECT_EQ(a.particles, b.particles);
      EXPECT_EQ(a.fit.mass, b.fit.mass);
      EXPECT_EQ(a.fit.rest_centroid, b.fit.rest_centroid);
      EXPECT_EQ(a.fit.centroid, b.fit.centroid);
      EXPECT_EQ(a.rotation, b.rotation);  // stored as a matrix too: exact
      EXPECT_EQ(a.translation, b.translation);
      EXPECT_LT((a.fit.rotation - b.fit.rotation).cwiseAbs().maxCoeff(), 4e-15);  // via quaternion
      EXPECT_EQ(a.fit.translation, b.fit.translation);
      EXPECT_EQ(a.fit.rms, b.fit.rms);
      EXPECT_EQ(a.fit.radius, b.fit.radius);
      EXPECT_EQ(a.blend, b.blend);
    }
  }
}

TEST_F(FragmentsFileTest, ByteLayout) {
  Fragment f;
  f.id = 3;
  f.particles = 9;
  f.fit.mass = 2.5;
  f.fit.rms = 0.25;
  f.fit.radius = 0.5;
  f.rotation = Eigen::AngleAxisd(-3.0, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
  f.translation = {1, 2, 3};
  const std::string p = path("f.pfg");
  write_fragments_file(p, 5, 6, 0.5, {f});
  const std::string b = read_all(p);
  ASSERT_EQ(b.size(), kFragmentsHeaderBytes + kFragmentRecordBytes);
  EXPECT_EQ(b.substr(0, 8), std::string("PFRAGS\0\0", 8));
  auto at = [&](size_t offset, auto value) {
    std::memcpy(&value, b.data() + offset, sizeof value);
    return value;
  };
  EXPECT_EQ(at(8, uint32_t()), 1u);
  EXPECT_EQ(at(12, uint32_t()), 280u);
  EXPECT_EQ(at(16, uint64_t()), 1u);
  EXPECT_EQ(at(24, int64_t()), 5);
  EXPECT_EQ(at(32, int64_t()), 6);
  EXPECT_EQ(at(40, double()), 0.5);
  const size_t r = kFragmentsHeaderBytes;
  EXPECT_EQ(at(r + 0, int32_t()), 3);
  EXPECT_EQ(at(r + 4, int32_t()), 9);
  EXPECT_EQ(at(r + 8, double()), 2.5);
  // Quaternion w x y z with w >= 0: a turn of -3 rad about z is (cos 1.5, 0, 0, -sin 1.5) up to sign.
  EXPECT_NEAR(at(r + 64, double()), std::cos(1.5), 1e-15);
  EXPECT_NEAR(at(r + 88, double()), -std::sin(1.5), 1e-15);
  EXPECT_EQ(at(r + 96, double()), f.rotation(0, 0));
  EXPECT_EQ(at(r + 104, double()), f.rotation(0, 1));
  EXPECT_EQ(at(r + 168, double()), 1.0);
  EXPECT_EQ(at(r + 184, double()), 3.0);
  EXPECT_EQ(at(r + 248, double()), 0.25);
  EXPECT_EQ(at(r + 256, double()), 0.5);
  EXPECT_EQ(at(r + 264, double()), 0.5);  // residual = rms / radius
  EXPECT_EQ(at(r + 272, double()), 0.0);
}

TEST_F(FragmentsFileTest, RefusesBadFiles) {
  const std::string p = path("f.pfg");
  write_fragments_file(p, 1, 2, 3, random_fragments(2, 9));
  const std::string good = read_all(p);
  auto expect_refused = [&](const std::string& bytes, const std::string& reason) {
    write_file_atomic(p, bytes);
    try {
      read_fragments_file(p);
      ADD_FAILURE() << "accepted: " << reason;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  };
  expect_refused(good.substr(0, 20), "truncated");
  expect_refused("X" + good.substr(1), "bad magic");
  std::string v = good;
  v[8] = 9;
  expect_refused(v, "unknown version 9");
  std::string rec = good;
  rec[12] = 1;
  expect_refused(rec, "record size");
  expect_refused(good.substr(0, good.size() - 1), "does not match");
  expect_refused(good + "x", "does not match");
  std::string huge = good;
  huge[23] = 0x7f;
  expect_refused(huge, "does not match");
  std::string not_finite = good;  // the first fragment's translation's x (record offset 168)
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&not_finite[kFragmentsHeaderBytes + 168], &nan, 8);
  expect_refused(not_finite, "not finite");
  EXPECT_THROW(read_fragments_file(path("missing.pfg")), IoError);
}

TEST(FragmentsFileName, FiveDigits) {
  EXPECT_EQ(fragments_file_name(42), "fragments_00042.pfg");
  EXPECT_EQ(fragments_file_name(123456), "fragments_123456.pfg");
}

}  // namespace
}  // namespace pd
