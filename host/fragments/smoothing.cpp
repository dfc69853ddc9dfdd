#include "host/fragments/smoothing.h"

#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace pd {

namespace {

// A pose shown for a set of particles: x -> rotation (x - rest_centroid) + centroid.
struct Pose {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d rest_centroid, centroid;
};

// `fit` with a correction of weight w applied about its centroid.
Pose corrected(const RigidFit& fit, const Eigen::Quaterniond& rotation, const Eigen::Vector3d& offset,
               double w) {
  if (w == 0) return {fit.rotation, fit.rest_centroid, fit.centroid};
  return {Eigen::Quaterniond::Identity().slerp(w, rotation).toRotationMatrix() * fit.rotation,
          fit.rest_centroid, fit.centroid + w * offset};
}

}  // namespace

FragmentSmoother::FragmentSmoother(int blend_frames) : frames_(blend_frames) {
  if (blend_frames < 0) throw std::invalid_argument("FragmentSmoother: blend_frames must be >= 0");
}

double FragmentSmoother::weight(int age) const {
  if (age < 0 || age >= frames_) return 0;
  const double u = double(age) / frames_;
  return 1 - u * u * u * (10 + u * (-15 + 6 * u));
}

bool FragmentSmoother::refines(const Components& c) const {
  if (previous_index_.size() != c.id.size()) return false;
  for (size_t k = 0; k < c.count(); ++k) {
    const int32_t parent = previous_index_[size_t(c.component_id(k))];
    for (int32_t m = c.start[k]; m < c.start[k + 1]; ++m)
      if (previous_index_[size_t(c.members[size_t(m)])] != parent) return false;
  }
  return true;
}

void FragmentSmoother::apply(const Components& c, const std::vector<Vec3>& rest,
                             const std::vector<Vec3>& current, const std::vector<real>& mass,
                             std::vector<Fragment>& fragments) {
  const size_t n = c.id.size();
  if (fragments.size() != c.count() || rest.size() != n || current.size() != n || mass.size() != n)
    throw std::invalid_argument(
        "FragmentSmoother::apply: fragments or per-particle arrays do not match the components");
  if (frames_ == 0) return;
  // Checked here: fit_rigid's own check would throw inside the parallel loop.
  for (size_t i = 0; i < n; ++i)
    if (!(mass[i] > 0))
      throw std::invalid_argument("FragmentSmoother::apply: particle " + std::to_string(i) +
                                  " has mass <= 0");
  const bool blend = refines(c);
  const int64_t count = int64_t(c.count());

  // Parents that split (their particle count changed), numbered in order of their first child:
  // slot[p] is parent p's number, -1 when it did not split.
  std::vector<int32_t> parent(c.count(), -1), slot(blend ? previous_.size() : 0, -1), split_parent;
  if (blend)
    for (size_t k = 0; k < c.count(); ++k) {
      const int32_t p = parent[k] = previous_index_[size_t(c.component_id(k))];
      if (previous_[size_t(p)].particles != c.size(k) && slot[size_t(p)] < 0) {
        slot[size_t(p)] = int32_t(split_parent.size());
        split_parent.push_back(p);
      }
    }

  // Where each split parent would be shown now: its particles fitted at this frame, with its own
  // correction one frame older. Members are grouped by parent (counting sort) to fit them.
  const int64_t splits = int64_t(split_parent.size());
  auto split_of = [&](size_t i) { return slot[size_t(previous_index_[i])]; };  // of particle i
  std::vector<int32_t> start(size_t(splits) + 1, 0), members;
  for (size_t i = 0; i < n && splits > 0; ++i)
    if (split_of(i) >= 0) ++start[size_t(split_of(i)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  members.resize(size_t(start.back()));
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (size_t i = 0; i < n && splits > 0; ++i)
    if (split_of(i) >= 0) members[size_t(fill[size_t(split_of(i))]++)] = int32_t(i);
  std::vector<Pose> parent_pose(static_cast<size_t>(splits));
#pragma omp parallel for schedule(dynamic, 16)
  for (int64_t p = 0; p < splits; ++p) {
    const RigidFit fit =
        fit_rigid(rest.data(), current.data(), mass.data(), members.data() + start[size_t(p)],
                  size_t(start[size_t(p) + 1] - start[size_t(p)]));
    const Correction& pc = previous_[size_t(split_parent[size_t(p)])];
    parent_pose[size_t(p)] = corrected(fit, pc.rotation, pc.offset, weight(pc.age < 0 ? -1 : pc.age + 1));
  }

  // Each fragment: inherit its correction, or at a split take the one that puts its fit onto the
  // parent's pose; then show the fit with the faded correction.
  next_.assign(c.count(), Correction());
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < count; ++k) {
    Fragment& f = fragments[size_t(k)];
    Correction& s = next_[size_t(k)];
    s.particles = f.particles;
    if (blend) {
      const Correction& pc = previous_[size_t(parent[size_t(k)])];
      const int32_t split = slot[size_t(parent[size_t(k)])];
      if (split < 0) {
        if (pc.age >= 0) s = {f.particles, pc.rotation, pc.offset, pc.age + 1};
      } else {
        const Pose& pp = parent_pose[size_t(split)];
        s.rotation = Eigen::Quaterniond(pp.rotation * f.fit.rotation.transpose()).normalized();
        s.offset = pp.rotation * (f.fit.rest_centroid - pp.rest_centroid) + pp.centroid - f.fit.centroid;
        s.age = 0;
      }
    }
    const double w = weight(s.age);
    if (w == 0) s.age = -1;
    const Pose shown = corrected(f.fit, s.rotation, s.offset, w);
    f.rotation = shown.rotation;
    f.translation = shown.centroid - shown.rotation * shown.rest_centroid;
    f.blend = w;
  }
  std::swap(previous_, next_);
  previous_index_ = c.index;
}

}  // namespace pd
