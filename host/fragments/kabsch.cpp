#include "host/fragments/kabsch.h"

#include <cmath>
#include <stdexcept>

namespace pd {

namespace {

// Kabsch on n points read through p(k), q(k), w(k) (double), two passes for accuracy: centroids
// first, then the covariance of the centred points and the residual.
template <class P, class Q, class W>
RigidFit fit_points(size_t n, P p, Q q, W w) {
  RigidFit fit;
  // Weighted centroids.
  for (size_t k = 0; k < n; ++k) {
    const double wk = w(k);
    if (!(wk >= 0)) throw std::invalid_argument("fit_rigid: weights must be >= 0");
    fit.mass += wk;
    fit.rest_centroid += wk * p(k);
    fit.centroid += wk * q(k);
  }
  if (!(fit.mass > 0)) throw std::invalid_argument("fit_rigid: no positive weight");
  fit.rest_centroid /= fit.mass;
  fit.centroid /= fit.mass;
  // One point: translation only (the common case once a body shatters; no SVD needed).
  if (n == 1) {
    fit.translation = fit.centroid - fit.rest_centroid;
    return fit;
  }

  // Cross-covariance H = sum w (p - p0)(q - q0)^T and the rest spread.
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  double spread = 0;
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d a = p(k) - fit.rest_centroid, b = q(k) - fit.centroid;
    h.noalias() += w(k) * a * b.transpose();
    spread += w(k) * a.squaredNorm();
  }
  fit.radius = std::sqrt(spread / fit.mass);

  // Rotation maximising tr(R H): R = V diag(1, 1, d) U^T with d = sign det(V U^T), so it is never
  // a reflection. With rank(H) <= 1 the SVD's other axes are arbitrary: use the smallest rotation
  // taking the rest line onto the current one instead, or none at all for H = 0.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  const Eigen::Matrix3d& u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  if (s(0) > 0 && s(1) > 1e-9 * s(0)) {
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (v * u.transpose()).determinant() < 0 ? -1 : 1;
    fit.rotation = v * d * u.transpose();
  } else if (s(0) > 0) {
    fit.rotation = Eigen::Quaterniond::FromTwoVectors(u.col(0), v.col(0)).toRotationMatrix();
  }
  fit.translation = fit.centroid - fit.rotation * fit.rest_centroid;

  // Residual of the fit.
  double misfit = 0;
  for (size_t k = 0; k < n; ++k)
    misfit += w(k) * (fit.rotation * (p(k) - fit.rest_centroid) - (q(k) - fit.centroid)).squaredNorm();
  fit.rms = std::sqrt(misfit / fit.mass);
  return fit;
}

Eigen::Vector3d to_eigen(Vec3 a) {
  return {double(a.x), double(a.y), double(a.z)};
}

}  // namespace

RigidFit fit_rigid(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& current,
                   const Eigen::VectorXd& weight) {
  if (rest.cols() != current.cols() || rest.cols() != weight.size())
    throw std::invalid_argument("fit_rigid: rest, current and weight differ in length");
  return fit_points(
      size_t(rest.cols()), [&](size_t k) -> Eigen::Vector3d { return rest.col(Eigen::Index(k)); },
      [&](size_t k) -> Eigen::Vector3d { return current.col(Eigen::Index(k)); },
      [&](size_t k) { return weight(Eigen::Index(k)); });
}

RigidFit fit_rigid(const Vec3* rest, const Vec3* current, const real* weight, const int32_t* members,
                   size_t n) {
  return fit_points(
      n, [&](size_t k) { return to_eigen(rest[members[k]]); },
      [&](size_t k) { return to_eigen(current[members[k]]); },
      [&](size_t k) { return double(weight[members[k]]); });
}

}  // namespace pd
