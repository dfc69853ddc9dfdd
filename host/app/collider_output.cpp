#include "host/app/collider_output.h"

#include <algorithm>
#include <cmath>

#include "host/geometry/collider_mesh.h"
#include "host/io/collider_file.h"
#include "host/io/frame.h"

namespace pd {
namespace {

// Half the side of the square a plane is drawn as: twice the particles' extent.
double plane_half_side(const SimulationInput& in) {
  const auto& rest = in.particles.rest;
  if (rest.empty()) return 1;
  Vec3 lo = rest[0], hi = rest[0];
  for (const Vec3& p : rest) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return std::max(1e-3, 2 * double(length(hi - lo)));
}

std::string vtu_name(int64_t frame) {
  return "colliders_" + frame_file_name(frame, "vtu").substr(6);  // "frame_" -> "colliders_"
}

}  // namespace

ColliderOutput::ColliderOutput(const std::string& dir, const SimulationInput& in,
                               const std::vector<TriMesh>& meshes, bool write_vtk)
    : dir_(dir), write_vtk_(write_vtk), series_(dir, "colliders") {
  if (in.colliders.empty()) return;
  const double plane_half = plane_half_side(in);
  for (size_t k = 0; k < in.colliders.size(); ++k) {
    const Collider& c = in.colliders[k];
    if (c.shape == kColliderMesh) {
      shapes_.push_back(meshes.at(k));
      masses_.push_back(in.motion.colliders[k].free() ? in.motion.colliders[k].mass : 0.0);
      continue;
    }
    const double size =
        double(c.shape == kColliderBox ? std::min(c.size.x, std::min(c.size.y, c.size.z)) : c.size.x);
    shapes_.push_back(collider_mesh(c, std::max(size, 1e-6) / 4, plane_half));
    masses_.push_back(
        k < in.motion.colliders.size() && in.motion.colliders[k].free() ? in.motion.colliders[k].mass : 0.0);
  }
  write_collider_obj(shapes_, dir_ + "/colliders.obj");
}

void ColliderOutput::write_frame(int64_t frame, double time, const std::vector<Collider>& colliders) {
  if (shapes_.empty()) return;
  std::vector<ColliderState> states;
  for (size_t k = 0; k < colliders.size(); ++k) states.push_back({colliders[k], masses_[k]});
  write_colliders_file(dir_ + "/" + colliders_file_name(frame), frame, time, states);
  if (!write_vtk_) return;
  TriangleSurface s;
  for (size_t k = 0; k < colliders.size(); ++k) {
    const TriMesh m = posed_mesh(shapes_[k], colliders[k]);
    const int32_t base = int32_t(s.points.size() / 3);
    for (const Vec3d& v : m.vertices)
      for (double x : v) s.points.push_back(float(x));
    for (const Triangle& t : m.triangles) {
      for (int32_t corner : t) s.triangles.push_back(base + corner);
      s.part.push_back(int32_t(k));
    }
  }
  const std::string name = vtu_name(frame);
  write_vtu_triangles(dir_ + "/" + name, time, s);
  series_.add(time, name);
}

void ColliderOutput::restore(const std::vector<PvdSeries::Entry>& particle_entries) {
  if (shapes_.empty() || !write_vtk_) return;
  std::vector<PvdSeries::Entry> entries;
  for (const PvdSeries::Entry& e : particle_entries)
    entries.push_back({e.time, "colliders_" + e.file.substr(e.file.find('_') + 1)});
  series_.restore(std::move(entries));
}

}  // namespace pd
