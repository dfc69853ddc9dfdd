// Triangulation of a planar region bounded by closed loops (outer boundaries counter-clockwise,
// holes clockwise, none crossing another), for the parts of Voronoi faces inside an object: holes
// are bridged into the loop around them, then each loop is cut into triangles by ear clipping.
// Every loop vertex ends up in a triangle, collinear ones included, so the triangles meet the
// neighbouring faces without T-junctions.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace pd {

struct Point2 {
  double x, y;
};

// `loops`: indices into `points`. Returns triangles of those indices, counter-clockwise.
std::vector<std::array<int32_t, 3>> triangulate_loops(const std::vector<std::vector<int32_t>>& loops,
                                                      const std::vector<Point2>& points);

// Twice the signed area of a loop (positive counter-clockwise).
double twice_area(const std::vector<int32_t>& loop, const std::vector<Point2>& points);

}  // namespace pd
