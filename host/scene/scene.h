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

#include "host/scene/scene_render.h"

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

// A number as a user wrote it (%g), for messages.
std::string format_number(double v);

// Bounds of a run's length (scene keys and command-line options alike): a billion frames of a
// billion steps keeps the step counter far from overflowing.
inline constexpr int64_t kMaxFrames = 1000000000;
inline constexpr int64_t kMaxStepsPerFrame = 1000000000;

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
      fracture_energy;  // G0 [J/m^2] -> tau (pmb_lattice_critical_stretch); exactly one of the two
  double strain_limit_scatter = 0.02;      // relative standard deviation of the normal scatter, in [0, 0.5]
  double compression_alpha = 0.25;         // alpha of Levine eq. 5, >= 0
  std::optional<bool> partial_volumes;     // default: true for state_based, false for bond_based
  std::optional<bool> surface_correction;  // default: true for bond_based, false for state_based
  // surface_correction = "ghosts": the ghost correction instead of the factors
  // (cuda/kernels/surface_ghosts.h); surface_correction then reads false.
  bool surface_ghosts = false;
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
  // grid particles: centres on the lattice origin + spacing (i, j, k) inside the shape, its surface
  // included (LAMMPS's `lattice sc` + `create_atoms` in a region); default: centred in the shape
  std::optional<Vec3d> lattice_origin;
};

// A keyframe of a path: {time [s], x, y, z [m]}.
using SceneKeyframe = std::array<double, 4>;

// Particles inside the axis-aligned box (of one body, or of all) follow a prescribed motion
// whatever the forces on them: grips, clamps, frames (held fixed by default). The motion is a
// constant velocity, or a keyframed translation path, plus an optional constant rotation about
// a pivot; from `release` on the particles are free.
struct SceneAnchor {
  Vec3d box_min{0, 0, 0}, box_max{0, 0, 0};
  std::string body;                 // only this body's particles; empty: every body
  Vec3d velocity{0, 0, 0};          // [m/s]
  std::vector<SceneKeyframe> path;  // translation offsets from the rest pose; excludes velocity
  Vec3d angular_velocity{0, 0, 0};  // [rad/s] about `pivot`
  std::optional<Vec3d> pivot;       // rest-space centre of rotation; default: the box centre
  std::optional<double> release;    // time [s] from which the particles move freely
};

struct SceneProjectile {
  Vec3d center{0, 0, 0};            // at t = 0 [m]
  Vec3d velocity{0, 0, 0};          // constant [m/s]
  std::vector<SceneKeyframe> path;  // keyframed centre instead of center + velocity
  double radius = 0;                // r [m], > 0
  double strength = 0;              // K_S [Pa], >= 0
};

// A rigid collider: an analytic shape that pushes the particles it touches (penalty contact with
// Coulomb friction and damping, cuda/kernels/colliders.h), fixed or moving on a script.
struct SceneCollider {
  std::string shape;                      // "plane" | "sphere" | "box" | "capsule" | "cylinder" | "mesh"
  Vec3d center{0, 0, 0};                  // at t = 0 [m]; a point of the plane
  Vec3d velocity{0, 0, 0};                // constant [m/s]
  std::vector<SceneKeyframe> path;        // keyframed centre instead of center + velocity
  Vec3d axis{0, 1, 0};                    // plane normal; capsule, cylinder and box: the shape's y axis
  Vec3d angular_velocity{0, 0, 0};        // [rad/s] about the centre
  double radius = 0;                      // sphere, capsule, cylinder [m]
  double length = 0;                      // capsule (segment) and cylinder [m]
  Vec3d size{0, 0, 0};                    // box: full extents along its axes [m]
  std::optional<double> stiffness;        // K [Pa]; default: the largest Young's modulus of the materials
  double friction = 0;                    // dynamic Coulomb coefficient, >= 0
  std::optional<double> static_friction;  // >= friction; default: friction
  double damping = 0.2;                   // of the normal push, as a ratio of critical damping, in [0, 1]
  std::string law = "penalty";            // "penalty" | "lammps_indent" (K (R - r)^2 V, K in N/m^5)
  std::optional<double> mass;     // [kg]: a free rigid body (not a plane), moved by the particles and gravity
  std::optional<double> density;  // [kg/m^3]: the same, its mass from its volume
  std::string mesh;               // mesh: an OBJ/PLY/STL file as written in the scene
  std::string mesh_path;          // mesh: resolved against the scene file's folder
  double scale = 1;               // mesh: uniform scale of the file's coordinates
  std::optional<double> cell;     // mesh: the distance grid's spacing [m]; default from the particles
};

// A pre-crack (strength 0: the bonds crossing it are removed before the run) or a weakened
// surface (strength in (0, 1) scales the strain limit of the bonds crossing it): an artist's
// control over where things break (Chen Fig. 17's pre-cracked sheet, the notched glass plate,
// Levine's randomly weakened glass). The surface is a set of triangles (host/scene/scene_cracks.h).
struct SceneCrack {
  std::string shape = "quad";      // "quad" | "path" | "random_walk" | "mesh"
  std::array<Vec3d, 4> corners{};  // quad: corners in order around it [m]
  std::vector<Vec3d> points;       // path: a polyline [m]
  Vec3d extrude{0, 0, 0};          // path, random_walk: the ribbon spans the line +- extrude/2 [m]
  Vec3d start{0, 0, 0};            // random_walk: where every walk starts [m]
  int64_t walks = 6;               // random_walk: number of walks, spread around start
  int64_t steps = 20;              // random_walk: steps per walk
  double step_length = 0;          // random_walk: [m], > 0
  double turn = 30;                // random_walk: largest change of direction per step [degrees]
  std::string mesh;                // mesh: triangles of an OBJ/PLY/STL file (need not be closed)
  std::string mesh_path;           // mesh: resolved against the scene file's folder
  double scale = 1;                // mesh: uniform scale of the file's coordinates
  Vec3d translate{0, 0, 0};        // mesh: moved by this after scaling [m]
  double strength = 0;             // in [0, 1)
  std::string body;                // only this body's bonds; empty: every body
};

// Particles whose rest position lies in the region (of one body, or of all) get another strain
// limit: `strain_limit` replaces the material's base value (before the scatter) and
// `strain_limit_factor` multiplies the result. A painted or mesh-given weak (or strong) zone.
struct SceneRegion {
  std::string shape = "box";                 // "box" | "sphere" | "mesh" (a closed mesh)
  Vec3d box_min{0, 0, 0}, box_max{0, 0, 0};  // box [m]
  Vec3d center{0, 0, 0};                     // sphere [m]
  double radius = 0;                         // sphere [m]
  std::string mesh, mesh_path;               // mesh, resolved against the scene file's folder
  double scale = 1;                          // mesh
  Vec3d translate{0, 0, 0};                  // mesh [m]
  std::string body;                          // only this body's particles; empty: every body
  std::optional<double> strain_limit;        // in (0, 1)
  double strain_limit_factor = 1;            // > 0
};

// Shards: a body breaks along the faces of Voronoi cells about `size` across (seeds on a grid of
// that spacing, each moved within its cell by `jitter`), and holds inside them: every strain
// limit of the body is multiplied by `hold`, and a bond between two cells keeps the limit it had
// (strength 1 / hold). The smallest piece is then a cell, not a particle (issue 31's dust).
// With `radius`, only the particles within it of `center` (rest positions) are cut into cells,
// and the zone's edge is a face too: where a blow crushes, pieces of cells instead of grit, and
// elsewhere the cracks the material makes.
struct SceneShards {
  double size = 0;               // cell spacing [m], > 0
  double hold = 3;               // in (1, 255]
  double jitter = 1;             // in [0, 1]: 0 a cubic grid of cells, 1 seeds anywhere in their grid cell
  std::string body;              // only this body; empty: every body
  Vec3d center{0, 0, 0};         // the zone's centre [m] (with radius)
  std::optional<double> radius;  // the zone's radius [m], > 0; none: the whole body
  // A pattern: instead of cells, the faces are the bonds broken in a finished run of the same
  // scene (its output folder's checkpoint), and `size` groups that run's dust into cells
  // (host/app/shards_pattern.h applies it; assign_shards leaves such a table alone).
  std::string pattern, pattern_path;  // as written; resolved against the scene file's folder
  // With a pattern: how much the dust's cells hold inside, in (1, 255]; none: `hold`.
  std::optional<double> dust_hold;
};

struct Scene {
  std::string path;         // file it was read from
  std::string description;  // one line

  // [simulation]
  double dt = 0x1p-23;            // time step [s], > 0
  bool dt_auto = false;           // dt = "auto": half the stable time step of the stiffest material
  int64_t steps_per_frame = 500;  // 1 to kMaxStepsPerFrame
  int64_t frames = 30;            // 0 (the set-up and frame 0 only) to kMaxFrames
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
  std::vector<SceneCollider> colliders;      // [[colliders]], at most kMaxColliders
  std::vector<SceneCrack> cracks;            // [[cracks]]
  std::vector<SceneRegion> regions;          // [[regions]]
  std::vector<SceneShards> shards;           // [[shards]]

  // [output]
  bool write_vtk = true;
  bool write_binary = true;

  std::optional<SceneRender> render;  // [render]: render frames while running
};

// Reads and validates a scene file. Throws SceneError for every user mistake (unreadable
// file, TOML syntax, unknown key, wrong type, value out of range, dangling material name).
// `overrides` are "KEY=VALUE" settings applied on top of the file before it is validated
// (`perifrac run --set`): KEY a dotted path such as materials.glass.bulk_modulus or
// projectiles[0].strength, VALUE a TOML value (2.94e8, "glass", [0, 1, 0], true).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
// Same, from text (tests); `path` is used in messages only.
Scene parse_scene(const std::string& text, const std::string& path,
                  const std::vector<std::string>& overrides = {});

}  // namespace pd
