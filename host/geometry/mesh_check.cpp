#include "host/geometry/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <unordered_map>

#include "host/geometry/inside_test.h"

namespace pd {

namespace {

std::string count_text(size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Merges vertices with bit-identical coordinates (OBJ seams, STL-like exports) and returns how many.
int weld_identical(TriMesh& mesh) {
  std::map<Vec3d, int32_t> first;
  std::vector<int32_t> remap(mesh.vertices.size());
  std::vector<Vec3d> kept;
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto [it, inserted] = first.emplace(mesh.vertices[v], int32_t(kept.size()));
    if (inserted) kept.push_back(mesh.vertices[v]);
    remap[v] = it->second;
  }
  const int merged = int(mesh.vertices.size() - kept.size());
  if (merged == 0) return 0;
  mesh.vertices = std::move(kept);
  for (Triangle& t : mesh.triangles)
    for (int32_t& c : t) c = remap[c];
  return merged;
}

// Each vertex's first earlier vertex within `distance` (itself where none is): a hash of cells of
// side `distance`, each vertex looking in the 27 cells around it.
std::vector<int32_t> near_vertices(const std::vector<Vec3d>& vertices, double distance) {
  std::vector<int32_t> to(vertices.size());
  for (size_t v = 0; v < to.size(); ++v) to[v] = int32_t(v);
  if (vertices.empty() || !(distance > 0)) return to;
  std::unordered_map<uint64_t, std::vector<int32_t>> cells;
  auto cell_key = [](int64_t x, int64_t y, int64_t z) {
    return (uint64_t(x) * 73856093u) ^ (uint64_t(y) * 19349663u) ^ (uint64_t(z) * 83492791u);
  };
  Box3d box;
  for (const Vec3d& v : vertices) box.add(v);
  // Cells counted from the box's corner, at most (its size / distance) + 1 along an axis.
  const double most = 1e15;
  for (size_t v = 0; v < vertices.size(); ++v) {
    int64_t c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = int64_t(std::min(most, std::floor((vertices[v][a] - box.lo[a]) / distance)));
    for (int64_t dz = -1; dz <= 1 && to[v] == int32_t(v); ++dz)
      for (int64_t dy = -1; dy <= 1 && to[v] == int32_t(v); ++dy)
        for (int64_t dx = -1; dx <= 1 && to[v] == int32_t(v); ++dx) {
          const auto it = cells.find(cell_key(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == cells.end()) continue;
          for (int32_t w : it->second)  // merged into w's own target, when that is near too
            if (distance2(vertices[v], vertices[size_t(to[size_t(w)])]) <= distance * distance) {
              to[v] = to[size_t(w)];
              break;
            }
        }
    cells[cell_key(c[0], c[1], c[2])].push_back(int32_t(v));
  }
  return to;
}

// Merges vertices within kWeldDistance of the diagonal of each other; returns how many.
int weld_near(TriMesh& mesh) {
  const std::vector<int32_t> to = near_vertices(mesh.vertices, kWeldDistance * norm(bounds(mesh).size()));
  std::vector<int32_t> remap(mesh.vertices.size());
  std::vector<Vec3d> kept;
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (to[v] == int32_t(v)) {
      remap[v] = int32_t(kept.size());
      kept.push_back(mesh.vertices[v]);
    } else {
      remap[v] = remap[size_t(to[v])];
    }
  }
  const int merged = int(mesh.vertices.size() - kept.size());
  mesh.vertices = std::move(kept);
  for (Triangle& t : mesh.triangles)
    for (int32_t& c : t) c = remap[size_t(c)];
  // Triangles that lost a corner to the merge (two corners one vertex now) are left out.
  mesh.triangles.erase(
      std::remove_if(mesh.triangles.begin(), mesh.triangles.end(),
                     [](const Triangle& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }),
      mesh.triangles.end());
  return merged;
}

// How many boundary vertices have another boundary vertex within kWeldDistance of the diagonal:
// an open mesh whose pieces are a round-off apart rather than a mesh with holes.
size_t near_boundary_vertices(const TriMesh& mesh, const std::vector<std::vector<int32_t>>& loops) {
  std::vector<Vec3d> boundary;
  for (const auto& loop : loops)
    for (int32_t v : loop) boundary.push_back(mesh.vertices[size_t(v)]);
  const std::vector<int32_t> to = near_vertices(boundary, kWeldDistance * norm(bounds(mesh).size()));
  size_t near = 0;
  for (size_t v = 0; v < to.size(); ++v) near += to[v] != int32_t(v);
  return near;
}

// Half-edge a->b of triangle t, grouped by the undirected edge {min, max}.
struct HalfEdge {
  uint64_t key;  // min << 32 | max
  int32_t from, to, triangle;
};

std::vector<HalfEdge> sorted_half_edges(const TriMesh& mesh) {
  std::vector<HalfEdge> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const int32_t a = mesh.triangles[t][c], b = mesh.triangles[t][(c + 1) % 3];
      const uint64_t key = (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
      edges.push_back({key, a, b, int32_t(t)});
    }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  return edges;
}

std::string edge_text(const HalfEdge& e) {
  return std::to_string(e.from) + "-" + std::to_string(e.to);
}

// Edge topology: refuses non-manifold and inconsistently oriented edges; returns the boundary
// half-edges (edges used by one triangle).
std::vector<HalfEdge> check_edges(const TriMesh& mesh, const std::string& path) {
  const std::vector<HalfEdge> edges = sorted_half_edges(mesh);
  std::vector<HalfEdge> boundary;
  size_t non_manifold = 0, misoriented = 0;
  const HalfEdge* first_non_manifold = nullptr;
  const HalfEdge* first_misoriented = nullptr;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 1) {
      boundary.push_back(edges[i]);
    } else if (j - i > 2) {
      if (!non_manifold++) first_non_manifold = &edges[i];
    } else if (edges[i].from == edges[i + 1].from) {
      if (!misoriented++) first_misoriented = &edges[i];
    }
    i = j;
  }
  if (non_manifold)
    throw MeshError(path, count_text(non_manifold, "edge is", "edges are") +
                              " shared by more than two triangles (non-manifold; first: vertices " +
                              edge_text(*first_non_manifold) +
                              ", 0-based) (allowed: a manifold mesh, each edge shared by two triangles)");
  if (misoriented)
    throw MeshError(path, count_text(misoriented, "edge has", "edges have") +
                              " both its triangles running the same way (inconsistent orientation; first: "
                              "vertices " +
                              edge_text(*first_misoriented) +
                              ", 0-based) (allowed: consistently oriented triangles)");
  return boundary;
}

// Loops of boundary half-edges; MeshError when a vertex has two outgoing boundary edges.
// repair_offered: whether the message offers repair = "fill_holes" (MeshCheckOptions).
std::vector<std::vector<int32_t>> trace_loops(const std::vector<HalfEdge>& boundary, const std::string& path,
                                              bool repair_offered) {
  std::unordered_map<int32_t, int32_t> next;
  for (const HalfEdge& e : boundary) {
    if (!next.emplace(e.from, e.to).second)
      throw MeshError(path,
                      "boundary vertex " + std::to_string(e.from) +
                          " (0-based) lies on two holes at once (a non-simple boundary loop) " +
                          (repair_offered ? "(allowed: a closed mesh, or holes with simple boundary loops "
                                            "for repair = \"fill_holes\")"
                                          : "(allowed: a closed mesh)"));
  }
  std::vector<std::vector<int32_t>> loops;
  std::unordered_map<int32_t, bool> used;
  for (const HalfEdge& e : boundary) {
    if (used[e.from]) continue;
    std::vector<int32_t> loop;
    int32_t v = e.from;
    while (!used[v]) {
      used[v] = true;
      loop.push_back(v);
      const auto it = next.find(v);
      if (it == next.end()) break;
      v = it->second;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Closes each loop with a fan around a new vertex at its centroid. A boundary half-edge a->b
// belongs to a triangle, so the patch uses b->a: triangles (b, a, centroid).
void fill_loops(TriMesh& mesh, const std::vector<std::vector<int32_t>>& loops) {
  for (const auto& loop : loops) {
    Vec3d c{0, 0, 0};
    for (int32_t v : loop) c = c + mesh.vertices[v];
    c = (1.0 / double(loop.size())) * c;
    const int32_t center = int32_t(mesh.vertices.size());
    mesh.vertices.push_back(c);
    for (size_t k = 0; k < loop.size(); ++k)
      mesh.triangles.push_back({loop[(k + 1) % loop.size()], loop[k], center});
  }
}

void check_triangles(const TriMesh& mesh, const std::string& path) {
  const Box3d box = bounds(mesh);
  const double diag = norm(box.size());
  size_t degenerate = 0, first = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& f = mesh.triangles[t];
    const bool repeated = f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
    if (repeated || !(triangle_area(mesh, t) > 1e-14 * diag * diag))
      if (!degenerate++) first = t;
  }
  if (degenerate)
    throw MeshError(path, count_text(degenerate, "triangle is", "triangles are") +
                              " degenerate (a repeated corner or zero area; first: triangle " +
                              std::to_string(first) + ", 0-based) (allowed: triangles of non-zero area)");
}

// The closed parts of a mesh (triangles joined through their corners), each as a mesh of its own;
// none where the mesh is one part.
std::vector<TriMesh> mesh_parts(const TriMesh& mesh, std::vector<int32_t>& part_of_triangle) {
  std::vector<int32_t> root(mesh.vertices.size());
  for (size_t v = 0; v < root.size(); ++v) root[v] = int32_t(v);
  auto find = [&](int32_t v) {
    while (root[size_t(v)] != v) v = root[size_t(v)] = root[size_t(root[size_t(v)])];
    return v;
  };
  for (const Triangle& t : mesh.triangles)
    for (int c = 1; c < 3; ++c) {
      const int32_t a = find(t[0]), b = find(t[size_t(c)]);
      if (a != b) root[size_t(std::max(a, b))] = std::min(a, b);
    }
  part_of_triangle.assign(mesh.triangles.size(), 0);
  const int32_t first = mesh.triangles.empty() ? 0 : find(mesh.triangles[0][0]);
  if (std::all_of(mesh.triangles.begin(), mesh.triangles.end(),
                  [&](const Triangle& t) { return find(t[0]) == first; }))
    return {};  // one part: no copy
  std::vector<TriMesh> parts;
  std::unordered_map<int32_t, int32_t> part_of_root;
  std::vector<int32_t> local_index(mesh.vertices.size(), -1);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto [it, added] = part_of_root.emplace(find(mesh.triangles[t][0]), int32_t(parts.size()));
    if (added) parts.emplace_back();
    TriMesh& part = parts[size_t(it->second)];
    part_of_triangle[t] = it->second;
    Triangle local_t{};
    for (int c = 0; c < 3; ++c) {
      const int32_t v = mesh.triangles[t][size_t(c)];
      if (local_index[size_t(v)] < 0) {
        local_index[size_t(v)] = int32_t(part.vertices.size());
        part.vertices.push_back(mesh.vertices[size_t(v)]);
      }
      local_t[size_t(c)] = local_index[size_t(v)];
    }
    part.triangles.push_back(local_t);
  }
  return parts;
}

// Points that stand for a part in the nesting tests: its corners, edge midpoints and triangle
// centroids (a bar whose corners lie in the two arms of a U is not inside it: its edges' midpoints
// span the gap), up to kSamples spread over the list.
std::vector<Vec3d> part_samples(const TriMesh& part) {
  constexpr size_t kSamples = 4096;
  std::vector<Vec3d> all = part.vertices;
  for (const Triangle& t : part.triangles) {
    const Vec3d &a = part.vertices[size_t(t[0])], &b = part.vertices[size_t(t[1])],
                &c = part.vertices[size_t(t[2])];
    all.push_back(0.5 * (a + b));
    all.push_back((1.0 / 3) * (a + b + c));
  }
  if (all.size() <= kSamples) return all;
  std::vector<Vec3d> some(kSamples);
  for (size_t k = 0; k < kSamples; ++k) some[k] = all[k * all.size() / kSamples];
  return some;
}

// Orients a mesh of several closed parts by how they nest: a part inside no other faces out, a
// part inside one faces in (a cavity), a part inside that cavity out again, and so on. A part is
// inside another when all its samples are (part_samples); parts that cross (limbs modelled into
// a body) are on one level, both facing out, and the inside test fills their union; a cavity
// inside two crossing parts is one level down, and one facing in that lies within their union
// but inside neither stays a cavity. Returns how many parts it flipped, or -1 where the mesh has
// more than kMaxParts parts, left as they are.
// (A part facing in on its own made Voronoi cells of negative volume and TetGen a cavity.)
constexpr size_t kMaxParts = 20000;

struct PartsOriented {
  int flipped = 0;   // parts turned over; -1: more than kMaxParts, left as they are
  int crossing = 0;  // parts that cross another (some of their samples inside it, some not)
};

PartsOriented orient_parts(TriMesh& mesh) {
  std::vector<int32_t> part_of_triangle;
  const std::vector<TriMesh> parts = mesh_parts(mesh, part_of_triangle);
  if (parts.size() < 2) return {};
  if (parts.size() > kMaxParts) return {-1, 0};
  std::vector<Box3d> box;
  std::vector<double> volume, box_volume;
  std::vector<std::vector<Vec3d>> samples;
  for (const TriMesh& p : parts) {
    box.push_back(bounds(p));
    volume.push_back(signed_volume(p));
    samples.push_back(part_samples(p));
    const Vec3d size = box.back().size();
    box_volume.push_back(size[0] * size[1] * size[2]);
  }
  std::vector<std::unique_ptr<InsideTest>> test(parts.size());
  auto inside = [&](size_t d, const Vec3d& p) {
    if (!test[d]) test[d] = std::make_unique<InsideTest>(parts[d]);
    return test[d]->inside(p);
  };
  auto boxes = [&](size_t d, size_t c, bool hold) {  // d's box holds (or meets) c's
    for (int a = 0; a < 3; ++a)
      if (hold ? !(box[d].lo[a] <= box[c].lo[a] && box[c].hi[a] <= box[d].hi[a])
               : !(box[d].lo[a] <= box[c].hi[a] && box[c].lo[a] <= box[d].hi[a]))
        return false;
    return true;
  };
  // Largest boxes first: a part's containers come before it.
  std::vector<size_t> order(parts.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return box_volume[a] > box_volume[b]; });
  std::vector<int> level(parts.size(), 0);
  std::vector<bool> flip(parts.size(), false);
  PartsOriented out;
  for (size_t c = 0; c < parts.size(); ++c) {  // crossings, for the note
    bool crosses = false;
    for (size_t d = 0; d < parts.size() && !crosses; ++d) {
      if (d == c || !boxes(d, c, false)) continue;
      bool in = false, out_of = false;
      for (size_t k = 0; k < samples[c].size() && !(in && out_of); ++k)
        (inside(d, samples[c][k]) ? in : out_of) = true;
      crosses = in && out_of;
    }
    out.crossing += crosses;
  }
  for (size_t i = 0; i < order.size(); ++i) {
    const size_t c = order[i];
    for (size_t j = 0; j < i; ++j) {
      const size_t d = order[j];
      if (!boxes(d, c, true) || level[d] + 1 <= level[c]) continue;
      bool all = true;
      for (size_t k = 0; k < samples[c].size() && all; ++k) all = inside(d, samples[c][k]);
      if (all) level[c] = level[d] + 1;
    }
    flip[c] = (volume[c] < 0) != (level[c] % 2 == 1);
    if (flip[c] && volume[c] < 0) {  // facing in on level 0: a cavity in the union of crossing parts?
      bool in_union = true;
      for (size_t k = 0; k < samples[c].size() && in_union; ++k) {
        bool any = false;
        for (size_t d = 0; d < parts.size() && !any; ++d)
          any = d != c && boxes(d, c, false) && inside(d, samples[c][k]);
        in_union = any;
      }
      flip[c] = !in_union;
    }
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    if (flip[size_t(part_of_triangle[t])]) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  for (bool f : flip) out.flipped += f;
  return out;
}

}  // namespace

std::vector<std::vector<int32_t>> boundary_loops(const TriMesh& mesh, const std::string& path,
                                                 bool repair_offered) {
  return trace_loops(check_edges(mesh, path), path, repair_offered);
}

MeshReport check_solid(TriMesh& mesh, const std::string& path, const MeshCheckOptions& options) {
  MeshReport report;
  if (mesh.vertices.empty() || mesh.triangles.empty())
    throw MeshError(path, "the mesh is empty (allowed: a mesh with at least one triangle)");
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (double c : mesh.vertices[v]) {
      if (!std::isfinite(c))
        throw MeshError(path, "vertex " + std::to_string(v) +
                                  " (0-based) has a coordinate that is not a finite number (allowed: finite "
                                  "coordinates)");
      if (std::fabs(c) > 1e15) {  // (1e103 made the volume infinite)
        char text[160];
        std::snprintf(text, sizeof text,
                      "vertex %zu (0-based) has a coordinate of %g (allowed: coordinates within 1e15 "
                      "of the origin)",
                      v, c);
        throw MeshError(path, text);
      }
    }
  for (const Triangle& t : mesh.triangles)
    for (int32_t c : t)
      if (c < 0 || size_t(c) >= mesh.vertices.size())
        throw MeshError(path, "a triangle refers to vertex " + std::to_string(c) + " (allowed: 0.." +
                                  std::to_string(mesh.vertices.size() - 1) + ")");

  report.welded_vertices = options.weld_near ? weld_near(mesh) : weld_identical(mesh);
  if (report.welded_vertices)
    report.notes.push_back("merged " +
                           count_text(size_t(report.welded_vertices),
                                      options.weld_near ? "vertex" : "duplicate vertex",
                                      options.weld_near ? "vertices" : "duplicate vertices") +
                           (options.weld_near ? " within 1e-6 of the mesh's size of another" : ""));
  check_triangles(mesh, path);

  // Boundary: refuse, or fill the loops and check the patches like any triangle.
  const auto loops = boundary_loops(mesh, path, options.repair_offered);
  report.holes = int(loops.size());
  if (!loops.empty()) {
    size_t edges = 0;
    for (const auto& l : loops) edges += l.size();
    if (!options.fill_holes) {
      const size_t near = options.weld_near ? 0 : near_boundary_vertices(mesh, loops);
      const std::string apart =
          near ? "; " + count_text(near, "boundary vertex lies", "boundary vertices lie") +
                     " within 1e-6 of the mesh's size of another: faces exported apart, not holes"
               : "";
      throw MeshError(
          path, "the mesh is open: " + count_text(loops.size(), "hole", "holes") + " (boundary loops) with " +
                    count_text(edges, "boundary edge", "boundary edges") + apart +
                    (!options.repair_offered ? " (allowed: a closed mesh)"
                     : near ? " (allowed: a closed mesh, or repair = \"weld\" to merge such vertices)"
                            : " (allowed: a closed mesh, or repair = \"fill_holes\" to close simple "
                              "holes)"));
    }
    fill_loops(mesh, loops);
    check_triangles(mesh, path);
    check_edges(mesh, path);
    report.notes.push_back("filled " + count_text(loops.size(), "hole", "holes") + " (" +
                           std::to_string(edges) + " boundary edges) by fan triangulation");
  }

  // Orientation: outward normals give a positive volume; then part by part, by how parts nest.
  double volume = signed_volume(mesh);
  const double diag = norm(bounds(mesh).size()), none = 1e-12 * diag * diag * diag;
  if (volume < -none) {
    flip_orientation(mesh);
    report.flipped = true;
    report.notes.push_back("the triangles faced inward (negative signed volume): flipped");
    volume = -volume;
  }
  const PartsOriented parts = orient_parts(mesh);
  if (parts.flipped > 0) {
    report.notes.push_back(
        "flipped " + count_text(size_t(parts.flipped), "part", "parts") +
        " of the mesh to face out of the solid they bound (a part inside another bounds a cavity, "
        "facing into it)");
    volume = signed_volume(mesh);
  }
  if (parts.flipped < 0)
    report.notes.push_back("more than " + std::to_string(kMaxParts) +
                           " parts: each kept facing as modelled, not oriented by how they nest");
  if (parts.crossing > 0)
    report.notes.push_back(
        count_text(size_t(parts.crossing), "part crosses", "parts cross") +
        " another: grid particles fill their union; Voronoi cells count the walls inside it "
        "(their volumes wrong there) and TetGen refuses crossing faces");
  if (!(std::fabs(volume) > none))
    throw MeshError(path, "the mesh encloses no volume (allowed: a closed surface around a solid)");
  if (volume < 0) {
    flip_orientation(mesh);
    report.flipped = !report.flipped;
    report.notes.push_back("the triangles faced inward (negative signed volume): flipped");
  }
  return report;
}

}  // namespace pd
