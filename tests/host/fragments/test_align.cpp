// Per-fragment fits of a frame and the split blending of FragmentSmoother.
#include "host/fragments/align.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "host/fragments/smoothing.h"

namespace pd {
namespace {

Vec3 to_vec3(const Eigen::Vector3d& v) {
  return {real(v.x()), real(v.y()), real(v.z())};
}
Eigen::Vector3d to_eigen(Vec3 v) {
  return {v.x, v.y, v.z};
}

double max_abs(const Eigen::MatrixXd& m) {
  return m.cwiseAbs().maxCoeff();
}

std::vector<Fragment> aligned(const Components& c, const std::vector<Vec3>& rest,
                              const std::vector<Vec3>& now, const std::vector<real>& mass) {
  std::vector<Fragment> f;
  align_fragments(c, rest, now, mass, f);
  return f;
}

// Two 2x2x2 clusters of unit spacing: L (particles 0-7) at x in {0, 1}, R (8-15) at x in {3, 4}.
std::vector<Vec3> two_clusters() {
  std::vector<Vec3> rest;
  for (double x0 : {0.0, 3.0})
    for (int k = 0; k < 8; ++k) rest.push_back({real(x0 + (k & 1)), real((k >> 1) & 1), real((k >> 2) & 1)});
  return rest;
}

// Frame t: L slides along x and turns about z, R turns about y and rises, each about its centre.
std::vector<Vec3> moved(const std::vector<Vec3>& rest, double t) {
  const Eigen::Matrix3d rl = Eigen::AngleAxisd(0.05 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d rr = Eigen::AngleAxisd(-0.2 * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d cl(0.5, 0.5, 0.5), cr(3.5, 0.5, 0.5);
  std::vector<Vec3> out;
  for (size_t i = 0; i < rest.size(); ++i) {
    const Eigen::Vector3d x = to_eigen(rest[i]);
    out.push_back(to_vec3(i < 8 ? rl * (x - cl) + cl + Eigen::Vector3d(0.1 * t, 0, 0)
                                : rr * (x - cr) + cr + Eigen::Vector3d(0, 0.05 * t, 0)));
  }
  return out;
}

// Component ids of the clusters: one fragment, or L and R apart, optionally R's top half apart.
std::vector<int32_t> whole() {
  return std::vector<int32_t>(16, 0);
}
std::vector<int32_t> apart(bool r_split = false) {
  std::vector<int32_t> id(16, 0);
  for (int i = 8; i < 16; ++i) id[size_t(i)] = r_split && i >= 12 ? 12 : 8;
  return id;
}

TEST(AlignFragments, FitsEachComponent) {
  const std::vector<Vec3> rest = two_clusters(), now = moved(rest, 3);
  const std::vector<real> mass(16, real(2));
  // Particle 15 on its own: translation only.
  std::vector<int32_t> id = apart();
  id[15] = 15;
  const Components c = components_from_ids(id);
  const std::vector<Fragment> f = aligned(c, rest, now, mass);
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].id, 0);
  EXPECT_EQ(f[0].particles, 8);
  EXPECT_LT(max_abs(f[0].fit.rotation - Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitZ()).toRotationMatrix()),
            1e-6);
  EXPECT_LT(max_abs(f[1].fit.rotation - Eigen::AngleAxisd(-0.6, Eigen::Vector3d::UnitY()).toRotationMatrix()),
            1e-6);
  EXPECT_LT(f[0].fit.residual(), 1e-6);
  EXPECT_NEAR(f[0].fit.mass, 16, 1e-12);
  EXPECT_EQ(f[2].particles, 1);
  EXPECT_EQ(f[2].fit.rotation, Eigen::Matrix3d::Identity());
  EXPECT_LT(max_abs(f[2].fit.translation - (to_eigen(now[15]) - to_eigen(rest[15]))), 1e-6);
  for (const Fragment& g : f) {
    EXPECT_EQ(g.rotation, g.fit.rotation);
    EXPECT_EQ(g.translation, g.fit.translation);
    EXPECT_EQ(g.blend, 0);
  }
}

TEST(AlignFragments, ResidualShowsDeformation) {
  // L and R fitted as one fragment move differently: the fit is a compromise with a residual.
  const std::vector<Vec3> rest = two_clusters();
  const std::vector<real> mass(16, real(1));
  const Components c = components_from_ids(whole());
  EXPECT_LT(aligned(c, rest, moved(rest, 0), mass)[0].fit.residual(), 1e-7);
  const RigidFit bent = aligned(c, rest, moved(rest, 4), mass)[0].fit;
  EXPECT_GT(bent.residual(), 0.05);
  EXPECT_NEAR(bent.rms, bent.residual() * bent.radius, 1e-15);
  EXPECT_THROW(aligned(c, rest, moved(rest, 1), std::vector<real>(16, 0)), std::invalid_argument);
  EXPECT_THROW(aligned(c, rest, std::vector<Vec3>(3), mass), std::invalid_argument);
}

TEST(FragmentSmoother, WeightEasesOutOverBlendFrames) {
  const FragmentSmoother s(4);
  EXPECT_EQ(s.weight(0), 1);
  EXPECT_EQ(s.weight(2), 0.5);
  EXPECT_EQ(s.weight(4), 0);
  EXPECT_EQ(s.weight(-1), 0);
  EXPECT_GT(s.weight(1), s.weight(2));
  EXPECT_GT(s.weight(2), s.weight(3));
  EXPECT_GT(s.weight(3), 0);
  EXPECT_THROW(FragmentSmoother(-1), std::invalid_argument);
}

// Runs the smoother over frames 0.. with the given component ids per frame; returns the fragments
// of every frame.
std::vector<std::vector<Fragment>> run(int blend_frames, const std::vector<std::vector<int32_t>>& ids) {
  const std::vector<Vec3> rest = two_clusters();
  const std::vector<real> mass(16, real(1.5));
  FragmentSmoother smoother(blend_frames);
  std::vector<std::vector<Fragment>> out;
  for (size_t t = 0; t < ids.size(); ++t) {
    const Components c = components_from_ids(ids[t]);
    const std::vector<Vec3> now = moved(rest, double(t));
    std::vector<Fragment> f = aligned(c, rest, now, mass);
    smoother.apply(c, rest, now, mass, f);
    out.push_back(f);
  }
  return out;
}

TEST(FragmentSmoother, SplitStartsAtTheParentPoseAndBlendsToTheFit) {
  // One fragment for frames 0-1, split at frame 2, blended over 4 frames.
  std::vector<std::vector<int32_t>> ids = {whole(), whole()};
  for (int t = 2; t < 8; ++t) ids.push_back(apart());
  const auto frames = run(4, ids);

  // Frame 2: both pieces shown exactly with the fit of the whole at frame 2.
  const std::vector<Vec3> rest = two_clusters();
  const Fragment parent =
      aligned(components_from_ids(whole()), rest, moved(rest, 2), std::vector<real>(16, real(1.5)))[0];
  for (const Fragment& f : frames[2]) {
    EXPECT_LT(max_abs(f.rotation - parent.fit.rotation), 1e-12);
    EXPECT_LT(max_abs(f.translation - parent.fit.translation), 1e-12);
    EXPECT_EQ(f.blend, 1);
  }
  // Then the correction fades, and from blend_frames after the split the fit is shown.
  const FragmentSmoother weights(4);
  for (int t = 0; t < 8; ++t)
    for (const Fragment& f : frames[size_t(t)]) {
      const double expected = t < 2 ? 0 : weights.weight(t - 2);
      EXPECT_DOUBLE_EQ(f.blend, expected) << "frame " << t;
      if (expected == 0) {
        EXPECT_EQ(f.rotation, f.fit.rotation);
        EXPECT_EQ(f.translation, f.fit.translation);
      } else if (t > 2) {
        EXPECT_GT(max_abs(f.rotation - f.fit.rotation), 0) << "frame " << t;
      }
    }
}

TEST(FragmentSmoother, SplitWhileBlendingContinuesFromTheShownPose) {
  // R splits again at frame 3, one frame into its blend: its pieces start where R would be shown
  // at frame 3 had it stayed whole.
  std::vector<std::vector<int32_t>> once = {whole(), whole()}, twice = once;
  for (int t = 2; t < 6; ++t) {
    once.push_back(apart());
    twice.push_back(apart(t >= 3));
  }
  const auto a = run(4, once), b = run(4, twice);
  const Fragment& r_whole = a[3][1];
  ASSERT_EQ(b[3].size(), 3u);
  for (size_t k : {1, 2}) {
    EXPECT_LT(max_abs(b[3][k].rotation - r_whole.rotation), 1e-12);
    EXPECT_LT(max_abs(b[3][k].translation - r_whole.translation), 1e-12);
    EXPECT_EQ(b[3][k].blend, 1);
  }
}

TEST(FragmentSmoother, OffOrNotARefinementShowsTheFit) {
  // blend_frames 0: every frame shows the fit; a merge (not a split) restarts the history.
  for (const auto& frames : {run(0, {whole(), apart(), apart()}), run(3, {apart(), whole(), whole()})})
    for (const auto& frame : frames)
      for (const Fragment& f : frame) {
        EXPECT_EQ(f.rotation, f.fit.rotation);
        EXPECT_EQ(f.translation, f.fit.translation);
        EXPECT_EQ(f.blend, 0);
      }
}

TEST(FragmentSmoother, RejectsMismatchedInput) {
  const std::vector<Vec3> rest = two_clusters();
  const Components c = components_from_ids(apart());
  std::vector<Fragment> f = aligned(c, rest, rest, std::vector<real>(16, real(1)));
  FragmentSmoother s(2);
  EXPECT_THROW(s.apply(c, rest, rest, std::vector<real>(16, real(0)), f), std::invalid_argument);
  EXPECT_THROW(s.apply(c, rest, std::vector<Vec3>(2), std::vector<real>(16, real(1)), f),
               std::invalid_argument);
  f.pop_back();
  EXPECT_THROW(s.apply(c, rest, rest, std::vector<real>(16, real(1)), f), std::invalid_argument);
}

}  // namespace
}  // namespace pd
