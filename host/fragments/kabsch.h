// Procrustes superposition (Kabsch 1978; Levine sec. 4): the proper rigid motion that best takes
// a fragment's rest positions to its current positions in the mass-weighted least-squares sense.
// Computed in double whatever precision the simulation ran in.
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <cstdint>

#include "cuda/vec3.h"

namespace pd {

// current ~ rotation * rest + translation. rotation is always proper (det +1), never a reflection.
struct RigidFit {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d rest_centroid = Eigen::Vector3d::Zero();  // weighted centroids [m]
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double mass = 0;    // sum of the weights
  double rms = 0;     // weighted RMS distance between the moved rest points and the current ones [m]
  double radius = 0;  // weighted radius of gyration of the rest points [m]

  // How far from rigid the fragment moved: rms relative to its size (0 for a single point).
  double residual() const { return radius > 0 ? rms / radius : 0; }
};

// Fits point k of `rest` to point k of `current` with weight `weight[k]` (3 x n and n entries,
// weights >= 0 with a positive sum). One point (or all rest points coincident): translation only.
// Collinear rest points: the smallest rotation that aligns them (the spin about their line is
// undetermined). Throws std::invalid_argument for mismatched sizes or no positive weight.
RigidFit fit_rigid(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& current,
                   const Eigen::VectorXd& weight);

// The same for the n particles members[0..n) of shared per-particle arrays.
RigidFit fit_rigid(const Vec3* rest, const Vec3* current, const real* weight, const int32_t* members,
                   size_t n);

}  // namespace pd
