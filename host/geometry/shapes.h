// Procedural closed meshes, so scenes need no outside files. Each is centred on its bounding
// box's centre at the origin, with y as the axis of the round shapes, and outward triangles.
// `edge` is the target edge length (the particle spacing is a good choice): curved surfaces
// get about one vertex per `edge` along them.
#pragma once

#include <array>
#include <vector>

#include "host/geometry/tri_mesh.h"

namespace pd {

// Axis-aligned box of edge lengths `size`, two triangles per face.
TriMesh box_mesh(const Vec3d& size);

// Sphere of `radius`: a geodesic mesh (an icosahedron's faces cut into nearly equilateral
// triangles of about `edge`, projected onto the sphere).
TriMesh sphere_mesh(double radius, double edge);

// Closed cylinder along y: `radius`, `height`.
TriMesh cylinder_mesh(double radius, double height, double edge);

// Torus around y: `radius` from the axis to the tube's centre line, `tube_radius` of the tube.
TriMesh torus_mesh(double radius, double tube_radius, double edge);

// A vase along y: outer radius profile r(y) with its widest point `radius`, height `height`,
// a rounded foot of radius vase_foot(), open at the top, with a wall and a base of thickness
// `wall` (< vase_foot()), as a closed solid (the wall).
TriMesh vase_mesh(double radius, double height, double wall, double edge);

// Radius of the vase's rounded foot: min(radius / 4, height / 10).
double vase_foot(double radius, double height);

// The outer surface of the same vase alone: an open sheet (its rim is a boundary loop), for
// the fattened-shell particles, which thicken a sheet inward.
TriMesh vase_sheet(double radius, double height, double edge);

// Surface of revolution of a profile of (r, y) points around the y axis with `segments` around.
// Points with r = 0 become poles; a periodic profile (a closed loop, e.g. a circle) makes a torus.
// The result faces outward when the profile encloses area; open profiles give open sheets.
// With `edge` > 0 each ring gets only about one point per `edge` (at least 6, at most
// `segments`: see ring_segments), so rings near the axis have no slivers; 0 = `segments` on all.
TriMesh revolve(const std::vector<std::array<double, 2>>& profile, int segments, bool periodic,
                double edge = 0);

// Points on each ring of revolve(profile, segments, periodic, edge): 1 at a pole.
std::vector<int> ring_segments(const std::vector<std::array<double, 2>>& profile, int segments, bool periodic,
                               double edge);

}  // namespace pd
