// Per-fragment rigid transforms of a frame: one Procrustes fit per connected component, so that
// rest-space geometry of each piece can be drawn where the piece is now (Levine sec. 4).
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "host/fragments/components.h"
#include "host/fragments/kabsch.h"

namespace pd {

struct Fragment {
  int32_t id = 0;         // component id (smallest particle index in it)
  int32_t particles = 0;  // particles in it
  RigidFit fit;           // mass-weighted least-squares rigid motion rest -> current
  // The transform to render with: the fit itself, or while a split is blended (smoothing.h) the
  // fit composed with a fading correction; blend is that correction's remaining weight (0: none).
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double blend = 0;
};

// Fits every component of `c` (rest positions to current ones, weighted by mass) into `out`, in
// component order; rotation/translation are set to the fit. `out` is resized to c.count() and its
// storage reused, which matters when a body has shattered into many pieces. Throws
// std::invalid_argument for arrays whose length is not the particle count or a mass <= 0.
void align_fragments(const Components& c, const std::vector<Vec3>& rest, const std::vector<Vec3>& current,
                     const std::vector<real>& mass, std::vector<Fragment>& out);

}  // namespace pd
