#include "host/geometry/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>

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
    for (double c : mesh.vertices[v])
      if (!std::isfinite(c))
        throw MeshError(path, "vertex " + std::to_string(v) +
                                  " (0-based) has a coordinate that is not a finite number (allowed: finite "
                                  "coordinates)");
  for (const Triangle& t : mesh.triangles)
    for (int32_t c : t)
      if (c < 0 || size_t(c) >= mesh.vertices.size())
        throw MeshError(path, "a triangle refers to vertex " + std::to_string(c) + " (allowed: 0.." +
                                  std::to_string(mesh.vertices.size() - 1) + ")");

  report.welded_vertices = weld_identical(mesh);
  if (report.welded_vertices)
    report.notes.push_back(
        "merged " + count_text(size_t(report.welded_vertices), "duplicate vertex", "duplicate vertices"));
  check_triangles(mesh, path);

  // Boundary: refuse, or fill the loops and check the patches like any triangle.
  const auto loops = boundary_loops(mesh, path, options.repair_offered);
  report.holes = int(loops.size());
  if (!loops.empty()) {
    size_t edges = 0;
    for (const auto& l : loops) edges += l.size();
    if (!options.fill_holes)
      throw MeshError(
          path, "the mesh is open: " + count_text(loops.size(), "hole", "holes") + " (boundary loops) with " +
                    count_text(edges, "boundary edge", "boundary edges") +
                    (options.repair_offered
                         ? " (allowed: a closed mesh, or repair = \"fill_holes\" to close simple holes)"
                         : " (allowed: a closed mesh)"));
    fill_loops(mesh, loops);
    check_triangles(mesh, path);
    check_edges(mesh, path);
    report.notes.push_back("filled " + count_text(loops.size(), "hole", "holes") + " (" +
                           std::to_string(edges) + " boundary edges) by fan triangulation");
  }

  // Orientation: outward normals give a positive volume.
  const double volume = signed_volume(mesh);
  const double diag = norm(bounds(mesh).size());
  if (!(std::fabs(volume) > 1e-12 * diag * diag * diag))
    throw MeshError(path, "the mesh encloses no volume (allowed: a closed surface around a solid)");
  if (volume < 0) {
    flip_orientation(mesh);
    report.flipped = true;
    report.notes.push_back("the triangles faced inward (negative signed volume): flipped");
  }
  return report;
}

}  // namespace pd
