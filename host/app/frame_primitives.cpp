#include "host/app/frame_primitives.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pd {

namespace {

// Index of each particle's element in a per-element particle list (-1: none).
std::vector<int32_t> element_of(const std::vector<int32_t>& particle, size_t n, const char* what) {
  std::vector<int32_t> of(n, -1);
  for (size_t k = 0; k < particle.size(); ++k) {
    const int32_t p = particle[k];
    if (p < 0 || size_t(p) >= n)
      throw std::invalid_argument(std::string(what) + " of particle " + std::to_string(p) +
                                  " but the rest file has " + std::to_string(n) + " particles");
    of[size_t(p)] = int32_t(k);
  }
  return of;
}

Vec3 to_vec3(const Eigen::Vector3d& v) {
  return {real(v.x()), real(v.y()), real(v.z())};
}

// Appends particle i's cube: turned and moved by the fragment's rotation and translation, or
// axis-aligned where the rotation is the identity at float resolution.
void add_placed_cube(PrimitiveSet* prims, Vec3 rest, real half, const Eigen::Matrix3d& rotation,
                     const Eigen::Vector3d& translation) {
  const Vec3 centre = to_vec3(rotation * Eigen::Vector3d(rest.x, rest.y, rest.z) + translation);
  if ((rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= kAxisAlignedRotation) {
    prims->add_cube(centre, half);
    return;
  }
  const Vec3 axis[3] = {to_vec3(rotation.col(0)), to_vec3(rotation.col(1)), to_vec3(rotation.col(2))};
  prims->add_oriented_cube(centre, half, axis);
}

// Appends tetrahedron k of `tets` with its vertices moved by rotation and translation.
void add_placed_tet(PrimitiveSet* prims, const EmbeddedTets& tets, size_t k, const Eigen::Matrix3d& rotation,
                    const Eigen::Vector3d& translation) {
  Vec3 v[4];
  for (int c = 0; c < 4; ++c) {
    const Vec3d& p = tets.vertices[size_t(tets.tets[k][size_t(c)])];
    v[c] = to_vec3(rotation * Eigen::Vector3d(p[0], p[1], p[2]) + translation);
  }
  prims->add_tet(v[0], v[1], v[2], v[3]);
}

}  // namespace

void frame_primitives(const RestData& rest, const FrameData& frame, PrimitiveSet* prims,
                      std::vector<Vec3>* albedo, const RestTrimtopes* trimtopes,
                      const FragmentsFrame* fragments, const EmbeddedTets* tets, const RunLooks& looks) {
  const size_t n = rest.size();
  if (frame.size() != n || frame.damage.size() != n || frame.body.size() != n)
    throw std::invalid_argument("frame " + std::to_string(frame.frame) + " has " +
                                std::to_string(frame.size()) + " particles, the rest file " +
                                std::to_string(n) + " particles");
  // Which particles are trimtopes and which tetrahedra.
  const std::vector<int32_t> trimtope_of =
      trimtopes ? element_of(trimtopes->particle, n, "trimtope") : std::vector<int32_t>();
  const std::vector<int32_t> tet_of =
      tets ? element_of(tets->particle, n, "tetrahedron") : std::vector<int32_t>();
  // Fragment of each component id (ids are particle indices).
  std::vector<int32_t> fragment_of;
  if (fragments && frame.component.size() == n) {
    fragment_of.assign(n, -1);
    for (size_t f = 0; f < fragments->fragments.size(); ++f) {
      const int32_t id = fragments->fragments[f].id;
      if (id < 0 || size_t(id) >= n)
        throw std::invalid_argument("fragment id " + std::to_string(id) + " is not a particle index");
      fragment_of[size_t(id)] = int32_t(f);
    }
  }
  *prims = PrimitiveSet();
  albedo->clear();
  albedo->reserve(n);
  for (size_t i = 0; i < n; ++i) {
    albedo->push_back(particle_color(looks.of(frame.body[i]), frame.damage[i], looks.damage_colors));
    const int32_t trim = trimtope_of.empty() ? -1 : trimtope_of[i];
    const int32_t tet = tet_of.empty() ? -1 : tet_of[i];
    const real half = real(0.5) * std::cbrt(real(rest.volume[i]));
    // The fragment's rigid transform, else the particle's displacement (cubes: its position).
    const int32_t c = fragment_of.empty() ? -1 : frame.component[i];
    const int32_t f = c >= 0 && size_t(c) < n ? fragment_of[size_t(c)] : -1;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation;
    if (f >= 0) {
      const Fragment& fr = fragments->fragments[size_t(f)];
      rotation = fr.rotation;
      translation = fr.translation;
    } else {
      const Vec3 u = frame.position[i] - rest.position[i];
      translation = Eigen::Vector3d(u.x, u.y, u.z);
    }
    if (trim >= 0) {
      add_placed_trimtope(prims, *trimtopes, size_t(trim), rotation, translation);
    } else if (tet >= 0) {
      add_placed_tet(prims, *tets, size_t(tet), rotation, translation);
    } else if (f >= 0) {
      add_placed_cube(prims, rest.position[i], half, rotation, translation);
    } else {
      prims->add_cube(frame.position[i], half);
    }
  }
}

Box cube_bounds(const std::vector<Vec3>& positions, const std::vector<float>& volume) {
  Box b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (size_t i = 0; i < positions.size(); ++i) {
    const real h = real(0.5) * std::cbrt(real(volume[i]));
    b.lo = vmin(b.lo, positions[i] - Vec3{h, h, h});
    b.hi = vmax(b.hi, positions[i] + Vec3{h, h, h});
  }
  return b;
}

}  // namespace pd
