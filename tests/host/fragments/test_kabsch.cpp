// Procrustes fits: exact recovery of rigid motions, proper rotations only, least squares on noisy
// data (against Horn's quaternion method and brute-force perturbation), degenerate point sets.
#include "host/fragments/kabsch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "host/geometry/random.h"

namespace pd {
namespace {

Eigen::Matrix3d random_rotation(Random& rng) {
  Eigen::Quaterniond q(rng.normal(), rng.normal(), rng.normal(), rng.normal());
  return q.normalized().toRotationMatrix();
}

Eigen::Vector3d random_vector(Random& rng, double scale) {
  return scale * Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
}

// n points in a box of side `scale` around `center`.
Eigen::Matrix3Xd random_points(Random& rng, Eigen::Index n, const Eigen::Vector3d& center, double scale) {
  Eigen::Matrix3Xd p(3, n);
  for (Eigen::Index k = 0; k < n; ++k) p.col(k) = center + random_vector(rng, scale);
  return p;
}

Eigen::VectorXd random_weights(Random& rng, Eigen::Index n) {
  Eigen::VectorXd w(n);
  for (Eigen::Index k = 0; k < n; ++k) w(k) = 0.5 + 1.5 * rng.uniform();
  return w;
}

// Weighted squared misfit of x -> r (x - p0) + q0 with the optimal (centroid) translation.
double misfit(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& q, const Eigen::VectorXd& w,
              const Eigen::Matrix3d& r) {
  const Eigen::Vector3d p0 = p * w / w.sum(), q0 = q * w / w.sum();
  double sum = 0;
  for (Eigen::Index k = 0; k < p.cols(); ++k)
    sum += w(k) * (r * (p.col(k) - p0) - (q.col(k) - q0)).squaredNorm();
  return sum;
}

// Horn (1987): the optimal rotation is the unit quaternion of the largest eigenvalue of a
// symmetric 4x4 matrix built from the weighted cross-covariance. An independent method.
Eigen::Matrix3d horn_rotation(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& q,
                              const Eigen::VectorXd& w) {
  const Eigen::Vector3d p0 = p * w / w.sum(), q0 = q * w / w.sum();
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (Eigen::Index k = 0; k < p.cols(); ++k) s += w(k) * (p.col(k) - p0) * (q.col(k) - q0).transpose();
  const double xx = s(0, 0), xy = s(0, 1), xz = s(0, 2), yx = s(1, 0), yy = s(1, 1), yz = s(1, 2),
               zx = s(2, 0), zy = s(2, 1), zz = s(2, 2);
  Eigen::Matrix4d n;
  n << xx + yy + zz, yz - zy, zx - xz, xy - yx,  //
      yz - zy, xx - yy - zz, xy + yx, zx + xz,   //
      zx - xz, xy + yx, -xx + yy - zz, yz + zy,  //
      xy - yx, zx + xz, yz + zy, -xx - yy + zz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(n);
  const Eigen::Vector4d v = eig.eigenvectors().col(3);
  return Eigen::Quaterniond(v(0), v(1), v(2), v(3)).normalized().toRotationMatrix();
}

double max_abs(const Eigen::MatrixXd& m) {
  return m.cwiseAbs().maxCoeff();
}

TEST(Kabsch, RecoversRandomRigidMotionToRoundOff) {
  Random rng(11);
  for (Eigen::Index n : {3, 4, 5, 10, 100, 1000, 10000, 100000}) {
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::Vector3d center = random_vector(rng, 20);
      const Eigen::Matrix3Xd p = random_points(rng, n, center, 1.0);
      const Eigen::Matrix3d r = random_rotation(rng);
      const Eigen::Vector3d t = random_vector(rng, 10);
      const Eigen::Matrix3Xd q = (r * p).colwise() + t;
      const Eigen::VectorXd w = random_weights(rng, n);
      const RigidFit fit = fit_rigid(p, q, w);
      SCOPED_TRACE("n = " + std::to_string(n));
      EXPECT_LT(max_abs(fit.rotation - r), 1e-13);
      EXPECT_LT(max_abs(fit.translation - t), 1e-12);
      EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-14);
      EXPECT_LT(fit.rms, 1e-12);
      EXPECT_LT(fit.residual(), 1e-12);
      EXPECT_NEAR(fit.mass, w.sum(), 1e-9 * w.sum());
    }
  }
}

TEST(Kabsch, ReflectedInputGivesBestProperRotation) {
  Random rng(12);
  for (Eigen::Index n : {3, 4, 10, 1000}) {
    const Eigen::Matrix3Xd p = random_points(rng, n, Eigen::Vector3d(1, 2, 3), 1.0);
    // A mirror image: reflection through a random plane, then moved.
    const Eigen::Vector3d normal = random_vector(rng, 1).normalized();
    const Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity() - 2 * normal * normal.transpose();
    const Eigen::Matrix3Xd q = ((random_rotation(rng) * mirror) * p).colwise() + Eigen::Vector3d(-4, 0, 5);
    const Eigen::VectorXd w = random_weights(rng, n);
    const RigidFit fit = fit_rigid(p, q, w);
    SCOPED_TRACE("n = " + std::to_string(n));
    EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-12);
    EXPECT_LT(max_abs(fit.rotation * fit.rotation.transpose() - Eigen::Matrix3d::Identity()), 1e-13);
    // The optimum over proper rotations: Horn's answer, and no better rotation nearby.
    EXPECT_NEAR(misfit(p, q, w, fit.rotation), misfit(p, q, w, horn_rotation(p, q, w)), 1e-10);
    // Three points are always planar, and a mirrored planar set is a rotation of it.
    if (n > 3) {
      EXPECT_GT(fit.rms, 0.01);
    }
  }
}

TEST(Kabsch, MirroredPlanarSetIsARotation) {
  // Points in the plane z = 0 mirrored across x = 0 are the same points turned 180 degrees about
  // the y axis: the fit must find that rotation, not the reflection.
  Random rng(13);
  Eigen::Matrix3Xd p = random_points(rng, 50, Eigen::Vector3d::Zero(), 2.0);
  p.row(2).setZero();
  Eigen::Matrix3Xd q = p;
  q.row(0) *= -1;
  const RigidFit fit = fit_rigid(p, q, Eigen::VectorXd::Ones(50));
  EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-14);
  EXPECT_LT(fit.rms, 1e-13);
  const Eigen::Matrix3d half_turn_y = Eigen::Vector3d(-1, 1, -1).asDiagonal();
  EXPECT_LT(max_abs(fit.rotation - half_turn_y), 1e-13);
}

TEST(Kabsch, NoisyInputGivesLeastSquaresAnswer) {
  Random rng(14);
  for (Eigen::Index n : {3, 6, 50, 2000}) {
    const Eigen::Matrix3Xd p = random_points(rng, n, Eigen::Vector3d(0, 5, 0), 1.0);
    Eigen::Matrix3Xd q = (random_rotation(rng) * p).colwise() + random_vector(rng, 3);
    for (Eigen::Index k = 0; k < n; ++k)
      q.col(k) += 0.05 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    const Eigen::VectorXd w = random_weights(rng, n);
    const RigidFit fit = fit_rigid(p, q, w);
    SCOPED_TRACE("n = " + std::to_string(n));
    // Same rotation as Horn's method.
    EXPECT_LT(max_abs(fit.rotation - horn_rotation(p, q, w)), 1e-9);
    // Brute force: no small turn about any axis lowers the weighted misfit.
    const double best = misfit(p, q, w, fit.rotation);
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d axis = random_vector(rng, 1).normalized();
      const double angle = 1e-3 * (1 + trial % 10);
      const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
      EXPECT_GE(misfit(p, q, w, turn * fit.rotation), best * (1 - 1e-12));
    }
    // rms is the misfit, translation takes the centroid to the centroid.
    EXPECT_NEAR(fit.rms, std::sqrt(best / w.sum()), 1e-12);
    EXPECT_LT(max_abs(fit.rotation * fit.rest_centroid + fit.translation - fit.centroid), 1e-13);
  }
}

TEST(Kabsch, SinglePointIsTranslationOnly) {
  Eigen::Matrix3Xd p(3, 1), q(3, 1);
  p << 1, 2, 3;
  q << -1, 0.5, 7;
  const RigidFit fit = fit_rigid(p, q, Eigen::VectorXd::Constant(1, 2.5));
  EXPECT_EQ(fit.rotation, Eigen::Matrix3d::Identity());
  EXPECT_LT(max_abs(fit.translation - Eigen::Vector3d(-2, -1.5, 4)), 1e-15);
  EXPECT_EQ(fit.rms, 0);
  EXPECT_EQ(fit.radius, 0);
  EXPECT_EQ(fit.residual(), 0);
}

TEST(Kabsch, CollinearPointsGetTheSmallestRotation) {
  // Rest points on the x axis, current ones on a tilted line: the spin about the line is free,
  // the fit takes the smallest turn (axis perpendicular to both lines).
  Random rng(15);
  for (Eigen::Index n : {2, 7}) {
    Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Zero(3, n);
    for (Eigen::Index k = 0; k < n; ++k) p(0, k) = double(k) + 0.3 * rng.uniform();
    const Eigen::Vector3d dir = Eigen::Vector3d(1, 2, -0.5).normalized();
    const Eigen::Matrix3d smallest =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), dir).toRotationMatrix();
    const Eigen::Matrix3Xd q = (smallest * p).colwise() + Eigen::Vector3d(3, 3, 3);
    const RigidFit fit = fit_rigid(p, q, random_weights(rng, n));
    SCOPED_TRACE("n = " + std::to_string(n));
    EXPECT_LT(max_abs(fit.rotation - smallest), 1e-12);
    EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-14);
    EXPECT_LT(fit.rms, 1e-13);
  }
}

TEST(Kabsch, IndexedFloatInputMatchesEigenInput) {
  Random rng(16);
  std::vector<Vec3> rest, current;
  std::vector<real> mass;
  const Eigen::Matrix3d r = random_rotation(rng);
  for (int k = 0; k < 40; ++k) {
    const Eigen::Vector3d x = random_vector(rng, 1), y = r * x + Eigen::Vector3d(0.1, 0.2, 0.3);
    rest.push_back({real(x.x()), real(x.y()), real(x.z())});
    current.push_back({real(y.x()), real(y.y()), real(y.z())});
    mass.push_back(real(1 + rng.uniform()));
  }
  const std::vector<int32_t> members = {3, 5, 8, 13, 21, 34, 39};
  Eigen::Matrix3Xd p(3, 7), q(3, 7);
  Eigen::VectorXd w(7);
  for (int k = 0; k < 7; ++k) {
    const size_t i = size_t(members[size_t(k)]);
    p.col(k) << rest[i].x, rest[i].y, rest[i].z;
    q.col(k) << current[i].x, current[i].y, current[i].z;
    w(k) = mass[i];
  }
  const RigidFit a = fit_rigid(rest.data(), current.data(), mass.data(), members.data(), members.size());
  const RigidFit b = fit_rigid(p, q, w);
  EXPECT_LT(max_abs(a.rotation - b.rotation), 1e-15);
  EXPECT_LT(max_abs(a.translation - b.translation), 1e-15);
  EXPECT_LT(max_abs(a.rotation - r), 1e-6);  // float32 input
}

TEST(Kabsch, RejectsBadInput) {
  const Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Zero(3, 2);
  EXPECT_THROW(fit_rigid(p, Eigen::Matrix3Xd::Zero(3, 3), Eigen::VectorXd::Ones(2)), std::invalid_argument);
  EXPECT_THROW(fit_rigid(p, p, Eigen::VectorXd::Zero(2)), std::invalid_argument);
  EXPECT_THROW(fit_rigid(p, p, Eigen::VectorXd::Constant(2, -1)), std::invalid_argument);
}

}  // namespace
}  // namespace pd
