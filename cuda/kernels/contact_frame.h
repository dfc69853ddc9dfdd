// The frame the contact lists are kept in (ContactLists). A pair's distance is the same seen from
// any frame that translates without turning, so the argument that keeps the lists complete
// (contact_relist.h) holds with every position taken relative to a frame displaced by T(t): a
// particle's origin is its displacement less T at its list's build, and it has left its skin when
// its displacement less T now lies farther than its skin from that origin; its skin is sized by
// its speed relative to the frame. At each full build the lists take one of two frames: at rest
// (T = 0, the lists as they were), or moving with the particles' mean velocity V and the gravity
// g, T = V tau + g tau^2 / 2 after tau, where the particles move together (VelocityMoments): a
// body in free fall then stays inside its skins until it meets something, where at rest every
// particle of it left its skin every kContactStepsAhead steps (the vase at Levine's size before
// its impact: a full build every 32 steps).
#pragma once

#include <cmath>
#include <cstdint>

#include "cuda/views.h"

namespace pd {

// The particles' velocities and their squares summed in double: their mean is the moving frame's
// velocity, and their spread about it says whether the particles move together.
struct VelocityMoments {
  double x = 0, y = 0, z = 0, squares = 0;
};

PD_HD inline VelocityMoments operator+(const VelocityMoments& a, const VelocityMoments& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z, a.squares + b.squares};
}

PD_HD inline VelocityMoments velocity_moments_of(Vec3 v) {
  const double x = v.x, y = v.y, z = v.z;
  return {x, y, z, x * x + y * y + z * z};
}

// Whether the particles move together, as a body in flight does, so that the moving frame keeps
// their lists longer: their speeds relative to the mean velocity, in the mean square, under a
// hundredth of their mean-square speed (kMovingFrameSpread; a body in free fall: nearly none of
// it; particles at rest, or flying apart, or one in ten of them at rest: a hundredth or more).
// Looser bounds took the moving frame for bodies bouncing on the floor, whose particles there
// then leave their skins at the gravity's pace: a quarter slowed Chen's elastic drop 9%
// (bench/NOTES.md). False for non-finite velocities.
constexpr double kMovingFrameSpread = 0.01;

inline bool moving_frame_wins(const VelocityMoments& m, int64_t n) {
  if (n <= 0) return false;
  const double mean_square = m.squares / double(n);
  const double vx = m.x / double(n), vy = m.y / double(n), vz = m.z / double(n);
  const double spread = mean_square - (vx * vx + vy * vy + vz * vz);
  return std::isfinite(mean_square) && std::isfinite(spread) && mean_square > 0 &&
         spread < kMovingFrameSpread * mean_square;
}

}  // namespace pd
