// A scene as the user wrote it (SI units), after parsing and validation. The loader
// (scene_loader.cpp) fills it from TOML; scene_setup.cpp turns it into particles and
// kernel parameters. Every key is documented in docs/scene-reference.md.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene_render.h"

namespace pd {

using Vec3d = std::array<double, 3>;

// A user mistake in a scene: names the file, the key (dotted path, e.g. "bodies[0].spacing")
// and what is allowed. what() is the one-line message printed to the user.
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::string key, const std::string& message);
  const std::string& file() const { return file_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_, key_;
};

// Deviatoric plasticity of a state-based material (Chen et al. eqs. 10-15).
struct ScenePlastic {
  double psi0 =
      0;  // yield constant psi_0, given directly or from yield_stress: 25 sigma_Y^2 / (8 pi delta^5)
  std::optional<double> yield_stress;  // sigma_Y [Pa]; exactly one of yield_stress and psi0
  double limit = 0;                    // Chen's gamma as a stretch: |e^p| <= limit |xi|; 0 = no limit
};

// Anisotropy matrix G of the influence function omega = delta / |G xi| (Chen eq. 16).
struct SceneAnisotropy {
  std::array<double, 9> matrix{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row major
};

struct SceneMaterial {
  std::string name;
  std::string model = "bond_based";           // "bond_based" | "state_based"
  double density = 0;                         // rho [kg/m^3], > 0
  double bulk_modulus = 0;                    // K [Pa], > 0
  double shear_modulus = 0;                   // mu [Pa], > 0; state_based only
  std::string fracture = "chen";              // state_based: "chen" (eq. 18) or "stretch" (Levine's max rule)
  double damage_alpha = 0;                    // alpha of Chen eq. 18, >= 0
  std::optional<ScenePlastic> plastic;        // state_based only
  std::optional<SceneAnisotropy> anisotropy;  // state_based only
  double horizon = 3;                         // delta / lambda, >= 1
  std::optional<double> strain_limit;         // explicit critical stretch tau, in (0, 1)
  std::optional<double>
      fracture_energy;                 // G0 [J/m^2] -> tau = sqrt(5 G0 / (9 K delta)); exactly one of the two
  double strain_limit_scatter = 0.02;  // relative standard deviation of the normal scatter, in [0, 0.5]
  double compression_alpha = 0.25;     // alpha of Levine eq. 5, >= 0
  std::optional<bool> partial_volumes;  // default: true for state_based, false for bond_based
};

// A body: a solid (a procedural shape or a mesh file) filled with particles of one kind.
struct SceneBody {
  std::string name;
  std::string shape = "box";  // "box" | "plate" | "sphere" | "cylinder" | "torus" | "vase" | "mesh"
  std::string particles =
      "grid";             // "grid" (cubes) | "tets" (TetGen) | "shell" (fattened-shell tets) | "voronoi"
  Vec3d center{0, 0, 0};  // centre of the body's bounding box [m]
  Vec3d size{0, 0, 0};    // box: edge lengths [m], each > 0
  double width = 0, depth = 0, thickness = 0;  // plate: x, z and y extents [m]
  double radius = 0;                     // sphere, cylinder, vase (widest); torus: axis to tube centre [m]
  double height = 0;                     // cylinder, vase [m]
  double tube_radius = 0;                // torus [m]
  double wall = 0;                       // vase: wall and base thickness [m]
  std::string mesh;                      // mesh: file path as written in the scene
  std::string mesh_path;                 // mesh: the path resolved against the scene file's folder
  double scale = 1;                      // mesh: uniform scale applied to the file's coordinates
  std::string repair = "none";           // mesh: "none" | "fill_holes"
  double tet_quality = 1.414;            // tets/shell: TetGen -q radius-edge bound; 0 = no quality refinement
  std::optional<double> tet_max_volume;  // tets/shell: TetGen -a bound [m^3]; default 2 spacing^3
  bool tet_keep_surface = false;         // tets/shell: TetGen -Y, no Steiner points on the surface
  double shell_thickness = 0;            // shell: depth of the shell inward from the surface [m]
  int64_t shell_layers = 4;              // shell: surfaces of vertices through the thickness, >= 2
  double spacing = 0;       // lambda [m], > 0: grid cube side, Voronoi minimum distance, horizon unit
  std::string material;     // name of a [materials.NAME] table
  Vec3d velocity{0, 0, 0};  // initial velocity [m/s]
};

// Particles inside the axis-aligned box move with a prescribed constant velocity (held fixed
// by default), whatever the forces on them: grips, clamps, frames.
struct SceneAnchor {
  Vec3d box_min{0, 0, 0}, box_max{0, 0, 0};
  Vec3d velocity{0, 0, 0};  // [m/s]
};

struct SceneProjectile {
  Vec3d center{0, 0, 0};    // at t = 0 [m]
  Vec3d velocity{0, 0, 0};  // constant [m/s]
  double radius = 0;        // r [m], > 0
  double strength = 0;      // K_S [Pa], >= 0
};

struct Scene {
  std::string path;         // file it was read from
  std::string description;  // one line

  // [simulation]
  double dt = 0x1p-23;            // time step [s], > 0
  bool dt_auto = false;           // dt = "auto": half the stable time step of the stiffest material
  int64_t steps_per_frame = 500;  // >= 1
  int64_t frames = 30;            // >= 1
  uint64_t seed = 1;

  // [world]
  Vec3d gravity{0, -9.81, 0};
  bool floor = false;
  double floor_height = 0;
  double restitution = 0.99;  // in [0, 1]

  // [contact]
  bool contact = true;
  double contact_stiffness = 1e8;  // K_c [Pa], >= 0

  std::vector<SceneMaterial> materials;      // [materials.NAME], at least one
  std::vector<SceneBody> bodies;             // [[bodies]], at least one
  std::vector<SceneAnchor> anchors;          // [[anchors]]
  std::vector<SceneProjectile> projectiles;  // [[projectiles]], at most 4

  // [output]
  bool write_vtk = true;
  bool write_binary = true;

  std::optional<SceneRender> render;  // [render]: render frames while running
};

// Reads and validates a scene file. Throws SceneError for every user mistake (unreadable
// file, TOML syntax, unknown key, wrong type, value out of range, dangling material name).
Scene load_scene(const std::string& path);
// Same, from text (tests); `path` is used in messages only.
Scene parse_scene(const std::string& text, const std::string& path);

}  // namespace pd
