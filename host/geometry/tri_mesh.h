// Triangle surface meshes: the common form of every mesh file and procedural shape, and the
// error type of everything that reads or checks one.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/geometry/vec3d.h"

namespace pd {

// A problem with a mesh file or its contents: "<path>: <what is wrong> (allowed: ...)".
// An invalid_argument, so the command line reports it as a user mistake (exit code 2).
class MeshError : public std::invalid_argument {
 public:
  MeshError(std::string path, const std::string& message);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

using Triangle = std::array<int32_t, 3>;

struct TriMesh {
  std::vector<Vec3d> vertices;
  std::vector<Triangle> triangles;  // counter-clockwise seen from outside for a closed mesh
};

// Volume enclosed by a closed mesh: sum of the signed tetrahedra (origin, a, b, c) / 6.
// Positive when the triangles face outward.
double signed_volume(const TriMesh& mesh);

// Area of one triangle and of the whole surface.
double triangle_area(const TriMesh& mesh, size_t t);
double surface_area(const TriMesh& mesh);

Box3d bounds(const TriMesh& mesh);

// x -> scale * x + offset for every vertex.
void transform(TriMesh& mesh, double scale, const Vec3d& offset);

// Reverses every triangle's orientation (inside out).
void flip_orientation(TriMesh& mesh);

// Appends `other`'s vertices and triangles.
void append(TriMesh& mesh, const TriMesh& other);

// Parameter t in (0, 1) where the segment a + t (b - a) crosses triangle (p, q, r), or -1.
double segment_hits(const Vec3d& a, const Vec3d& b, const Vec3d& p, const Vec3d& q, const Vec3d& r);

}  // namespace pd
