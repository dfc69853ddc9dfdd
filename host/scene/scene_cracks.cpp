#include "host/scene/scene_cracks.h"

#include <cmath>
#include <memory>

#include "host/geometry/inside_test.h"
#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/random.h"
#include "host/geometry/vec3d.h"

namespace pd {

namespace {

constexpr double kPi = 3.14159265358979323846;

int32_t body_index(const Scene& scene, const std::string& name) {
  if (name.empty()) return -1;
  for (size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].name == name) return int32_t(b);
  return -1;  // the loader checked the name
}

// Two triangles of the quad a b c d.
void add_quad(std::vector<CutTriangle>& out, const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d,
              const CutTriangle& like) {
  CutTriangle t = like;
  t.corner = {a, b, c};
  out.push_back(t);
  t.corner = {a, c, d};
  out.push_back(t);
}

// The ribbon swept by a polyline along +-extrude/2.
void add_ribbon(std::vector<CutTriangle>& out, const std::vector<Vec3d>& line, const Vec3d& extrude,
                const CutTriangle& like) {
  const Vec3d half = 0.5 * extrude;
  for (size_t k = 0; k + 1 < line.size(); ++k)
    add_quad(out, line[k] - half, line[k + 1] - half, line[k + 1] + half, line[k] + half, like);
}

// A unit vector normal to n, and the one completing the right-handed frame.
void plane_basis(const Vec3d& n, Vec3d& e1, Vec3d& e2) {
  const Vec3d u = (1 / norm(n)) * n;
  const Vec3d helper = std::fabs(u[0]) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d a = cross(u, helper);
  e1 = (1 / norm(a)) * a;
  e2 = cross(u, e1);
}

TriMesh placed_mesh(const std::string& path, double scale, const Vec3d& translate, const std::string& file,
                    const std::string& key, bool closed) {
  try {
    TriMesh mesh = read_mesh(path);
    if (closed) check_solid(mesh, path, {});
    for (Vec3d& v : mesh.vertices) v = scale * v + translate;
    return mesh;
  } catch (const MeshError& e) {
    throw SceneError(file, key, e.what());
  }
}

}  // namespace

std::vector<std::vector<Vec3d>> random_walks(const SceneCrack& c, uint64_t seed) {
  Random rng(seed);
  Vec3d e1, e2;
  plane_basis(c.extrude, e1, e2);
  const double turn = c.turn * kPi / 180;
  std::vector<std::vector<Vec3d>> out;
  for (int64_t w = 0; w < c.walks; ++w) {
    double angle = 2 * kPi * (double(w) + rng.uniform() - 0.5) / double(c.walks);
    std::vector<Vec3d> line = {c.start};
    for (int64_t s = 0; s < c.steps; ++s) {
      line.push_back(line.back() + c.step_length * (std::cos(angle) * e1 + std::sin(angle) * e2));
      angle += turn * (2 * rng.uniform() - 1);
    }
    out.push_back(std::move(line));
  }
  return out;
}

std::vector<CutTriangle> crack_triangles(const Scene& scene) {
  std::vector<CutTriangle> out;
  for (size_t k = 0; k < scene.cracks.size(); ++k) {
    const SceneCrack& c = scene.cracks[k];
    CutTriangle like;
    like.strength = c.strength;
    like.body = body_index(scene, c.body);
    if (c.shape == "quad") add_quad(out, c.corners[0], c.corners[1], c.corners[2], c.corners[3], like);
    if (c.shape == "path") add_ribbon(out, c.points, c.extrude, like);
    if (c.shape == "random_walk")
      for (const auto& line : random_walks(c, scene.seed * 1000003u + k))
        add_ribbon(out, line, c.extrude, like);
    if (c.shape == "mesh") {
      const TriMesh mesh = placed_mesh(c.mesh_path, c.scale, c.translate, scene.path,
                                       "cracks[" + std::to_string(k) + "].mesh", false);
      for (const Triangle& t : mesh.triangles) {
        CutTriangle tri = like;
        tri.corner = {mesh.vertices[size_t(t[0])], mesh.vertices[size_t(t[1])], mesh.vertices[size_t(t[2])]};
        out.push_back(tri);
      }
    }
  }
  return out;
}

std::vector<std::function<bool(const Vec3d&)>> region_tests(const Scene& scene) {
  std::vector<std::function<bool(const Vec3d&)>> out;
  for (size_t k = 0; k < scene.regions.size(); ++k) {
    const SceneRegion& g = scene.regions[k];
    if (g.shape == "box") {
      out.push_back([g](const Vec3d& x) {
        for (int a = 0; a < 3; ++a)
          if (x[size_t(a)] < g.box_min[size_t(a)] || x[size_t(a)] > g.box_max[size_t(a)]) return false;
        return true;
      });
    } else if (g.shape == "sphere") {
      out.push_back([g](const Vec3d& x) { return distance2(x, g.center) <= g.radius * g.radius; });
    } else {
      auto mesh = std::make_shared<TriMesh>(placed_mesh(g.mesh_path, g.scale, g.translate, scene.path,
                                                        "regions[" + std::to_string(k) + "].mesh", true));
      auto test = std::make_shared<InsideTest>(*mesh);
      out.push_back([mesh, test](const Vec3d& x) { return test->inside(x); });
    }
  }
  return out;
}

}  // namespace pd
