// The entries shared by the libFuzzer targets (tests/fuzz/fuzz_*.cpp) and the regression test
// (tests/host/fuzz/test_fuzz_regressions.cpp). Each feeds bytes to one parser and to the
// validation that follows it, and holds them to the contract of every input: a valid result or
// a clean error (SceneError / MeshError starting with the file name, one line, saying what is
// allowed). A valid result is checked for consistency too. A broken contract throws
// ContractViolation, which no caller catches: a crash in the fuzzer, a failure in the test.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/views.h"
#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/scene/scene.h"

namespace pd::fuzz {

class ContractViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

inline void require(bool ok, const std::string& what) {
  if (!ok) throw ContractViolation("fuzz contract broken: " + what);
}

// A clean error: "<path>:...", one line of printable text, with the allowed values unless it is
// a TOML syntax error ("<path>:<line>:<column>: TOML syntax error: ...").
inline void require_clean_error(const std::string& message, const std::string& path) {
  require(message.size() > path.size() + 2 && message.compare(0, path.size() + 1, path + ":") == 0,
          "the error does not start with the file name: " + message);
  for (char c : message)
    require(static_cast<unsigned char>(c) >= 0x20 && c != 0x7f,
            "the error holds a control character (not one printable line)");
  const bool syntax = message.find(": TOML syntax error: ") != std::string::npos;
  require(syntax || message.find("(allowed: ") != std::string::npos,
          "the error does not say what is allowed: " + message);
}

// ---- Scene files -----------------------------------------------------------------------------

inline bool finite3(const Vec3d& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// Every value of a loaded scene within the ranges that docs/scene-reference.md promises.
inline void require_valid_scene(const Scene& s) {
  require(s.dt_auto || (std::isfinite(s.dt) && s.dt > 0), "dt");
  require(s.steps_per_frame >= 1 && s.steps_per_frame <= kMaxStepsPerFrame && s.frames >= 0 &&
              s.frames <= kMaxFrames,
          "steps_per_frame, frames");
  require(finite3(s.gravity) && std::isfinite(s.floor_height), "world");
  require(s.restitution >= 0 && s.restitution <= 1, "restitution");
  require(std::isfinite(s.contact_stiffness) && s.contact_stiffness >= 0, "contact stiffness");
  require(!s.materials.empty() && !s.bodies.empty(), "no material or no body");
  require(s.projectiles.size() <= static_cast<size_t>(kMaxProjectiles), "projectile count");
  for (const SceneMaterial& m : s.materials) {
    const bool state = m.model == "state_based";
    require(state || m.model == "bond_based", "material model");
    require(std::isfinite(m.density) && m.density > 0, "density of " + m.name);
    require(std::isfinite(m.bulk_modulus) && m.bulk_modulus > 0, "bulk_modulus of " + m.name);
    require(std::isfinite(m.shear_modulus) && (state ? m.shear_modulus > 0 : m.shear_modulus == 0),
            "shear_modulus of " + m.name);
    require(m.horizon >= 1 && m.horizon <= 12, "horizon of " + m.name);
    require(m.strain_limit.has_value() != m.fracture_energy.has_value(), "strength of " + m.name);
    require(!m.strain_limit || (*m.strain_limit > 0 && *m.strain_limit < 1), "strain_limit of " + m.name);
    require(!m.fracture_energy || (std::isfinite(*m.fracture_energy) && *m.fracture_energy > 0),
            "fracture_energy of " + m.name);
    require(m.strain_limit_scatter >= 0 && m.strain_limit_scatter <= 0.5, "scatter of " + m.name);
    require(std::isfinite(m.compression_alpha) && m.compression_alpha >= 0, "compression_alpha");
    require(std::isfinite(m.damage_alpha) && m.damage_alpha >= 0, "damage_alpha of " + m.name);
    if (m.plastic)
      require(std::isfinite(m.plastic->psi0) && std::isfinite(m.plastic->limit) && m.plastic->limit >= 0 &&
                  (m.plastic->yield_stress ? std::isfinite(*m.plastic->yield_stress) : m.plastic->psi0 > 0),
              "plastic of " + m.name);
    if (m.anisotropy) {
      const auto& g = m.anisotropy->matrix;
      for (double x : g) require(std::isfinite(x), "anisotropy matrix of " + m.name + " is not finite");
      const double det = g[0] * (g[4] * g[8] - g[5] * g[7]) - g[1] * (g[3] * g[8] - g[5] * g[6]) +
                         g[2] * (g[3] * g[7] - g[4] * g[6]);
      require(std::isfinite(det) && det != 0, "anisotropy matrix of " + m.name + " is singular");
    }
  }
  for (const SceneBody& b : s.bodies) {
    require(finite3(b.center) && finite3(b.size) && finite3(b.velocity), "body vectors of " + b.name);
    for (double x : {b.width, b.depth, b.thickness, b.radius, b.height, b.tube_radius, b.wall, b.scale,
                     b.tet_quality, b.shell_thickness})
      require(std::isfinite(x) && x >= 0, "body dimension of " + b.name);
    require(std::isfinite(b.spacing) && b.spacing > 0, "spacing of " + b.name);
    require(b.shape != "mesh" || (!b.mesh.empty() && !b.mesh_path.empty() && b.scale > 0), "mesh path");
    require(std::any_of(s.materials.begin(), s.materials.end(),
                        [&](const SceneMaterial& m) { return m.name == b.material; }),
            "dangling material of " + b.name);
  }
  for (const SceneAnchor& a : s.anchors) {
    require(finite3(a.box_min) && finite3(a.box_max) && finite3(a.velocity), "anchor vectors");
    for (int c = 0; c < 3; ++c) require(a.box_min[c] <= a.box_max[c], "anchor box");
  }
  for (const SceneProjectile& p : s.projectiles)
    require(finite3(p.center) && finite3(p.velocity) && std::isfinite(p.radius) && p.radius > 0 &&
                std::isfinite(p.strength) && p.strength >= 0,
            "projectile");
  if (s.render) {
    const SceneRender& r = *s.render;
    require((!r.eye || finite3(*r.eye)) && (!r.look_at || finite3(*r.look_at)), "render camera");
    require(!(r.eye && r.look_at && *r.eye == *r.look_at), "render eye at look_at");
    require(r.vfov > 0 && r.vfov < 180, "render vfov");
    require(r.width >= 16 && r.width <= 16384 && r.height >= 16 && r.height <= 16384, "render size");
    require(r.spp >= 1 && r.spp <= 1024 && r.every >= 1, "render spp, every");
    require(r.material == "opaque" || r.material == "glass", "render material");
    require(r.ior >= 1 && r.ior <= 4, "render ior");
    require(!r.environment.empty() && (r.environment == "sky") == r.environment_path.empty(),
            "render environment");
    require(s.write_binary, "render without binary frames");
  }
}

// Parses `bytes` as a scene file. Returns "" for a valid scene, else the clean error's message.
inline std::string scene_entry(const std::string& bytes) {
  const std::string path = "fuzz/input.toml";
  try {
    require_valid_scene(parse_scene(bytes, path));
    return "";
  } catch (const SceneError& e) {
    require_clean_error(e.what(), path);
    return e.what();
  }
}

// ---- Mesh files ------------------------------------------------------------------------------

enum class MeshFormat { obj, ply, stl };

// A mesh that check_solid accepted: finite, indices in range, no repeated corner, every edge
// shared by exactly two triangles running opposite ways (closed, oriented), positive volume.
inline void require_valid_solid(const TriMesh& mesh) {
  for (const Vec3d& v : mesh.vertices) require(finite3(v), "a vertex of an accepted mesh is not finite");
  std::vector<std::array<int32_t, 3>> edges;  // (min, max, +1 when min -> max else -1)
  for (const Triangle& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const int32_t a = t[c], b = t[(c + 1) % 3];
      require(a >= 0 && size_t(a) < mesh.vertices.size(), "a triangle index is out of range");
      require(a != b, "an accepted triangle repeats a corner");
      edges.push_back({std::min(a, b), std::max(a, b), a < b ? 1 : -1});
    }
  }
  std::sort(edges.begin(), edges.end());
  require(edges.size() % 2 == 0, "an odd number of half-edges in an accepted mesh");
  for (size_t i = 0; i < edges.size(); i += 2)
    require(edges[i][0] == edges[i + 1][0] && edges[i][1] == edges[i + 1][1] && edges[i][2] == -1 &&
                edges[i + 1][2] == 1 &&
                (i + 2 == edges.size() || edges[i + 2][0] != edges[i][0] || edges[i + 2][1] != edges[i][1]),
            "an accepted mesh is open, non-manifold or inconsistently oriented");
  require(signed_volume(mesh) > 0, "an accepted mesh does not enclose a positive volume");
}

// Parses `bytes` as a mesh file, then checks it as a solid without and with hole filling.
// Returns "" when the mesh is a usable solid (with repair = "fill_holes" where it has holes), else
// the clean error's message (the reader's, or the hole-filling check's).
inline std::string mesh_entry(MeshFormat format, const std::string& bytes) {
  const char* const names[] = {"fuzz/input.obj", "fuzz/input.ply", "fuzz/input.stl"};
  const std::string path = names[static_cast<int>(format)];
  auto clean = [&](const MeshError& e) {
    require(e.path() == path, "the error names another file");
    require_clean_error(e.what(), path);
    return std::string(e.what());
  };
  TriMesh mesh;
  try {
    mesh = format == MeshFormat::obj   ? parse_obj(bytes, path)
           : format == MeshFormat::ply ? parse_ply(bytes, path)
                                       : parse_stl(bytes, path);
  } catch (const MeshError& e) {
    return clean(e);
  }
  // What the readers promise: at least one triangle, every index naming a vertex.
  require(!mesh.triangles.empty(), "a parsed mesh has no triangle");
  for (const Triangle& t : mesh.triangles)
    for (int32_t c : t) require(c >= 0 && size_t(c) < mesh.vertices.size(), "a parsed index is out of range");
  std::string error;
  for (bool fill_holes : {false, true}) {
    TriMesh solid = mesh;
    try {
      const MeshReport report = check_solid(solid, path, {fill_holes});
      require(fill_holes || report.holes == 0, "holes reported without fill_holes");
      require_valid_solid(solid);
      error.clear();
    } catch (const MeshError& e) {
      error = clean(e);
    }
  }
  return error;
}

}  // namespace pd::fuzz
