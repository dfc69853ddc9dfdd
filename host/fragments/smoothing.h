// Blending of fragment transforms across splits. When the last bonds holding two chunks break,
// each chunk's Procrustes fit jumps from the compromise fit of the whole to its own, and rendered
// pieces pop (Levine sec. 7, "Limitations"). Here a chunk born from a split is first shown exactly
// where its parent would be shown at that frame (the parent's particles fitted at the frame of
// the split), and the difference to its own fit fades out over a few frames:
//
//   shown = C(w) * fit,   w = 1 - smootherstep(age / blend_frames),   age = frames since the split
//
// C is the correction taking the chunk's fit onto the parent's pose at the split; C(w) turns by
// w times C's rotation (slerp from the identity, about the chunk's centroid) and shifts by w times
// C's centroid offset. The weight starts at 1 with zero slope, falls without overshoot like a
// critically damped controller, and is 0 with zero slope after exactly blend_frames frames, so
// no state lingers. The chunk's own motion is never delayed: only the correction fades. A chunk
// that splits again while blending starts from where its parent is shown, so the shown motion
// stays continuous. Fragments are matched to the previous frame by particle membership:
// components only split, so each new one lies inside exactly one old one (its parent), and it is
// the same fragment when the sizes agree.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "host/fragments/align.h"
#include "host/fragments/components.h"

namespace pd {

class FragmentSmoother {
 public:
  // blend_frames = 0 turns smoothing off (every fragment is shown at its fit).
  explicit FragmentSmoother(int blend_frames);

  int blend_frames() const { return frames_; }

  // Sets rotation, translation and blend of `fragments` (align_fragments of `c` with the same
  // rest, current and mass arrays; the frame after the last call). When `c` is not a refinement of
  // the previous call's components (the first call, or frames from another run) nothing is
  // blended and the history restarts. Throws std::invalid_argument when the sizes do not match.
  void apply(const Components& c, const std::vector<Vec3>& rest, const std::vector<Vec3>& current,
             const std::vector<real>& mass, std::vector<Fragment>& fragments);

  // Weight of a split's correction `age` frames after it: 1 at age 0, 0 from blend_frames on.
  double weight(int age) const;

  // A fragment's correction, kept from frame to frame.
  struct Correction {
    int32_t particles = 0;
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // shift of the centroid [m]
    int age = -1;                                      // frames since the split; -1: none
  };
  // What carries over from one call to the next, for checkpoints.
  struct History {
    std::vector<int32_t> previous_index;
    std::vector<Correction> previous;
  };
  History history() const { return {previous_index_, previous_}; }
  void restore(History h) {
    previous_index_ = std::move(h.previous_index);
    previous_ = std::move(h.previous);
  }

 private:
  bool refines(const Components& c) const;

  int frames_;
  std::vector<int32_t> previous_index_;  // per particle: component number at the previous call
  std::vector<Correction> previous_;
  std::vector<Correction> next_;  // this call's, swapped with previous_ (storage reused)
};

}  // namespace pd
