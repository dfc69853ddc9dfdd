// Scene files: TOML parsed by toml++ (toml_document.h), then validated key by key into a pd::Scene
// (table_reader.h). Every user mistake becomes a SceneError "<file>: <key>: <what is wrong>
// (allowed: <what is allowed>)". The keys are documented in docs/scene-reference.md.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cuda/views.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tetgen.h"
#include "host/geometry/vec3d.h"
#include "host/io/input_file.h"
#include "host/scene/scene.h"
#include "host/scene/scene_overrides.h"
#include "host/scene/table_reader.h"
#include "host/scene/toml_document.h"
#include "render/looks.h"

namespace pd {

std::string format_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// A syntax error passes "<file>:<line>:<column>" as `file` and an empty key.
SceneError::SceneError(std::string file, std::string key, const std::string& message)
    : std::runtime_error(file + (key.empty() ? "" : ": " + key) + ": " + message),
      file_(std::move(file)),
      key_(std::move(key)) {}

namespace {

// ---- Sections ----------------------------------------------------------------------------------

const Keys kTopKeys = {"description", "simulation", "world",  "contact", "materials", "bodies", "anchors",
                       "projectiles", "colliders",  "cracks", "regions", "shards",    "output", "render"};
const Keys kSimulationKeys = {"dt", "steps_per_frame", "frames", "seed"};
const Keys kWorldKeys = {"gravity", "floor", "floor_height", "restitution"};
const Keys kContactKeys = {"enabled", "stiffness"};
const Keys kMaterialKeys = {"model",
                            "density",
                            "bulk_modulus",
                            "shear_modulus",
                            "youngs_modulus",
                            "poisson_ratio",
                            "horizon",
                            "strain_limit",
                            "fracture_energy",
                            "strain_limit_scatter",
                            "compression_alpha",
                            "partial_volumes",
                            "surface_correction",
                            "fracture",
                            "damage_alpha",
                            "plastic",
                            "anisotropy"};
const Keys kStateBasedOnlyKeys = {"shear_modulus", "youngs_modulus", "poisson_ratio",
                                  "fracture",      "plastic",        "anisotropy"};
const Keys kPlasticKeys = {"yield_stress", "psi0", "limit"};
const Keys kAnisotropyKeys = {"direction", "ratio", "matrix"};
const Keys kBodyKeys = {"name",
                        "shape",
                        "particles",
                        "center",
                        "size",
                        "width",
                        "depth",
                        "thickness",
                        "radius",
                        "height",
                        "tube_radius",
                        "wall",
                        "mesh",
                        "scale",
                        "repair",
                        "tet_quality",
                        "tet_max_volume",
                        "shell_thickness",
                        "shell_layers",
                        "spacing",
                        "material",
                        "velocity",
                        "tet_keep_surface",
                        "lattice_origin"};
const Keys kShapes = {"box", "plate", "sphere", "cylinder", "torus", "vase", "mesh"};
const Keys kParticleKinds = {"grid", "tets", "shell", "voronoi"};
// The dimension keys of each shape (in kShapes order).
const Keys kShapeKeys[] = {{"size"},
                           {"width", "depth", "thickness"},
                           {"radius"},
                           {"radius", "height"},
                           {"radius", "tube_radius"},
                           {"radius", "height", "wall"},
                           {"mesh", "scale", "repair"}};
const Keys kDimensionKeys = {"size",        "width", "depth", "thickness", "radius", "height",
                             "tube_radius", "wall",  "mesh",  "scale",     "repair"};
const Keys kAnchorKeys = {"box_min", "box_max",          "body",  "velocity",
                          "path",    "angular_velocity", "pivot", "release"};
const Keys kProjectileKeys = {"center", "velocity", "path", "radius", "strength"};
const Keys kColliderKeys = {"shape",   "center", "velocity", "path",      "axis",     "angular_velocity",
                            "radius",  "length", "size",     "stiffness", "friction", "static_friction",
                            "damping", "law",    "mass",     "density",   "mesh",     "scale",
                            "cell"};
const Keys kColliderLaws = {"penalty", "lammps_indent"};
const Keys kColliderShapes = {"plane", "sphere", "box", "capsule", "cylinder", "mesh"};
const Keys kCrackKeys = {"shape",       "corners", "points", "extrude", "start",     "walks",    "steps",
                         "step_length", "turn",    "mesh",   "scale",   "translate", "strength", "body"};
const Keys kCrackShapes = {"quad", "path", "random_walk", "mesh"};
// The geometry keys of each crack shape (in kCrackShapes order).
const Keys kCrackShapeKeys[] = {{"corners"},
                                {"points", "extrude"},
                                {"start", "extrude", "walks", "steps", "step_length", "turn"},
                                {"mesh", "scale", "translate"}};
const Keys kRegionKeys = {"shape",
                          "box_min",
                          "box_max",
                          "center",
                          "radius",
                          "mesh",
                          "scale",
                          "translate",
                          "body",
                          "strain_limit",
                          "strain_limit_factor"};
const Keys kRegionShapes = {"box", "sphere", "mesh"};
const Keys kRegionShapeKeys[] = {
    {"box_min", "box_max"}, {"center", "radius"}, {"mesh", "scale", "translate"}};
const Keys kShardKeys = {"size", "hold", "jitter", "body", "center", "radius", "pattern", "dust_hold"};
const Keys kOutputKeys = {"vtk", "binary"};
const Keys kRenderKeys = {"eye",           "look_at",  "vfov",          "width",       "height",
                          "spp",           "material", "ior",           "environment", "every",
                          "damage_colors", "surface",  "smooth_cracks", "bodies"};
const Keys kRenderBodyKeys = {"look", "color"};

const char* const kAxisNames[3] = {"x", "y", "z"};

// A box's `size`, required, every extent > 0 (a body's or a collider's).
void read_box_size(const TableReader& r, Vec3d& size) {
  r.vec3("size", size, Presence::required);
  for (int a = 0; a < 3; ++a)
    if (!(size[a] > 0))
      r.fail("size", std::string(kAxisNames[a]) + " size " + number_text(size[a]) + " is not > 0",
             "sizes > 0");
}
constexpr double kMaxHorizon = 12;  // delta / lambda; beyond this the bond families explode

// Elastic constants: bond_based takes the bulk modulus (its Poisson ratio is 1/4);
// state_based takes either (bulk_modulus, shear_modulus) or (youngs_modulus, poisson_ratio).
void parse_elastic_constants(const TableReader& r, SceneMaterial& m) {
  if (m.model == "bond_based") {
    for (const auto& key : kStateBasedOnlyKeys)
      if (r.has(key))
        r.fail(key, "only for model = \"state_based\"", "for bond_based: bulk_modulus (nu is 1/4)");
    r.number("bulk_modulus", m.bulk_modulus, greater_than(0), Presence::required);
    return;
  }
  const std::string pairs = "either bulk_modulus and shear_modulus, or youngs_modulus and poisson_ratio";
  const bool km = r.has("bulk_modulus") || r.has("shear_modulus");
  const bool enu = r.has("youngs_modulus") || r.has("poisson_ratio");
  if (km == enu)
    r.fail("", km ? "both kinds of elastic constants are given" : "no elastic constants are given", pairs);
  if (km) {
    r.number("bulk_modulus", m.bulk_modulus, greater_than(0), Presence::required);
    r.number("shear_modulus", m.shear_modulus, greater_than(0), Presence::required);
    return;
  }
  double e = 0, nu = 0;
  r.number("youngs_modulus", e, greater_than(0), Presence::required);
  r.number("poisson_ratio", nu, in_open(-1, 0.5), Presence::required);
  m.bulk_modulus = e / (3 * (1 - 2 * nu));
  m.shear_modulus = e / (2 * (1 + nu));
  // Near nu = 1/2 (or -1) a large Young's modulus overflows the moduli.
  if (!std::isfinite(m.bulk_modulus) || !std::isfinite(m.shear_modulus))
    r.fail(
        "youngs_modulus",
        "with poisson_ratio = " + number_text(nu) + " the bulk or shear modulus is not a finite number",
        "youngs_modulus and poisson_ratio whose K = E / (3 (1 - 2 nu)) and mu = E / (2 (1 + nu)) are finite");
}

ScenePlastic parse_plastic(const TableReader& r) {
  ScenePlastic p;
  double value = 0;
  const std::string one_of = "exactly one of yield_stress > 0 [Pa] and psi0 > 0";
  const bool stress = r.number("yield_stress", value, greater_than(0));
  if (stress) p.yield_stress = value;
  const bool psi = r.number("psi0", p.psi0, greater_than(0));
  if (stress == psi)
    r.fail("", stress ? "both yield_stress and psi0 are given" : "neither yield_stress nor psi0 is given",
           one_of);
  r.number("limit", p.limit, at_least(0));
  return p;
}

// G from a direction and a ratio (bonds along the direction weigh `ratio` times more:
// G = I + (1/ratio - 1) d d^T), or a full matrix.
SceneAnisotropy parse_anisotropy(const TableReader& r) {
  SceneAnisotropy a;
  const std::string one_of = "either direction and ratio, or matrix (9 numbers, row major)";
  const bool dir = r.has("direction") || r.has("ratio");
  if (dir == r.has("matrix"))
    r.fail("", dir ? "both direction/ratio and matrix are given" : "no anisotropy is given", one_of);
  if (!dir) {
    r.numbers("matrix", a.matrix, "an array of 9 numbers, G row major, non-singular");
    const auto& g = a.matrix;
    const double det = g[0] * (g[4] * g[8] - g[5] * g[7]) - g[1] * (g[3] * g[8] - g[5] * g[6]) +
                       g[2] * (g[3] * g[7] - g[4] * g[6]);
    if (!std::isfinite(det))
      r.fail("matrix", "the determinant of G overflows",
             "a non-singular 3x3 matrix with a finite determinant");
    if (!(std::fabs(det) > 1e-12)) r.fail("matrix", "G is singular", "a non-singular 3x3 matrix");
    return a;
  }
  Vec3d d{};
  double ratio = 1;
  r.vec3("direction", d, Presence::required);
  r.number("ratio", ratio, greater_than(0), Presence::required);
  // Normalised through its largest component, so that neither 1e200 nor 1e-200 over- or underflows.
  const double largest = std::max({std::fabs(d[0]), std::fabs(d[1]), std::fabs(d[2])});
  if (!(largest > 0)) r.fail("direction", "the direction is the zero vector", "a non-zero [x, y, z]");
  for (double& c : d) c /= largest;
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (double& c : d) c /= len;
  if (!std::isfinite(1 / ratio))
    r.fail("ratio", number_text(ratio) + " is too small: 1 / ratio overflows",
           "a number > 0 whose inverse is finite");
  if (!(1 / ratio > 1e-12))  // (the matrix form's bound: det G = 1 / ratio)
    r.fail("ratio", number_text(ratio) + " makes G singular", "a ratio below 1e12");
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      a.matrix[3 * row + col] = (row == col ? 1.0 : 0.0) + (1 / ratio - 1) * d[row] * d[col];
  return a;
}

SceneMaterial parse_material(const std::string& name, const TableReader& r) {
  SceneMaterial m;
  m.name = name;
  r.string("model", m.model, {"bond_based", "state_based"});
  r.number("density", m.density, greater_than(0), Presence::required);
  parse_elastic_constants(r, m);
  Bounds horizon = in_closed(1, kMaxHorizon);
  horizon.note = "the horizon delta in multiples of the spacing lambda, so delta >= lambda";
  r.number("horizon", m.horizon, horizon);

  // Strength: exactly one of an explicit strain limit and a fracture energy.
  double value = 0;
  if (r.number("strain_limit", value, in_open(0, 1))) m.strain_limit = value;
  if (r.number("fracture_energy", value, greater_than(0))) m.fracture_energy = value;
  const std::string one_of = "exactly one of strain_limit in (0, 1) and fracture_energy > 0";
  if (m.strain_limit && m.fracture_energy)
    r.fail("", "both strain_limit and fracture_energy are given", one_of);
  if (!m.strain_limit && !m.fracture_energy)
    r.fail("", "neither strain_limit nor fracture_energy is given", one_of);

  r.number("strain_limit_scatter", m.strain_limit_scatter, in_closed(0, 0.5));
  r.number("compression_alpha", m.compression_alpha, at_least(0));
  bool partial = false;
  if (r.boolean("partial_volumes", partial)) m.partial_volumes = partial;
  bool surface = false;
  if (r.is_string("surface_correction")) {
    std::string word;
    r.string("surface_correction", word, {"ghosts"});
    m.surface_correction = false;
    m.surface_ghosts = true;
  } else if (r.boolean("surface_correction", surface)) {
    m.surface_correction = surface;
  }

  // State-based extras: fracture criterion, plasticity, anisotropy.
  r.string("fracture", m.fracture, {"chen", "stretch"});
  r.number("damage_alpha", m.damage_alpha, at_least(0));
  if (r.has("plastic")) m.plastic = parse_plastic(r.table("plastic", kPlasticKeys));
  if (r.has("anisotropy")) m.anisotropy = parse_anisotropy(r.table("anisotropy", kAnisotropyKeys));
  if (m.anisotropy && (m.surface_correction.value_or(false) || m.surface_ghosts))
    r.fail("surface_correction",
           "is not available with anisotropy (its factors and ghosts assume an isotropic influence)",
           "false, or no anisotropy");
  if (m.plastic && m.surface_ghosts)
    r.fail("surface_correction",
           "\"ghosts\" is not available for plastic materials (ghost bonds keep no plastic history)",
           "true or false, or no [plastic] table");
  return m;
}

// A path as written in a scene: relative paths start from the scene file's folder.
std::string resolve_path(const std::string& scene_file, const std::string& path) {
  const size_t slash = scene_file.find_last_of('/');
  return path[0] == '/' || slash == std::string::npos ? path : scene_file.substr(0, slash + 1) + path;
}

// A `shape` key among `shapes`, with the geometry keys of the others refused; returns its index.
size_t parse_kind(const TableReader& r, std::string& shape, const Keys& shapes, const Keys* shape_keys) {
  r.string("shape", shape, shapes);
  const size_t s = size_t(std::find(shapes.begin(), shapes.end(), shape) - shapes.begin());
  for (size_t other = 0; other < shapes.size(); ++other)
    for (std::string_view key : shape_keys[other]) {
      const Keys& own = shape_keys[s];
      if (r.has(key) && std::find(own.begin(), own.end(), key) == own.end())
        r.fail(key, "not a key of shape = " + in_quotes(shape), "for " + shape + ": " + join(own, false));
    }
  return s;
}

// A body name that must name one of `bodies`.
void parse_body_name(const TableReader& r, std::string& out, const std::vector<SceneBody>& bodies) {
  if (!r.string("body", out)) return;
  Keys names;
  for (const SceneBody& b : bodies) names.push_back(b.name);
  if (std::find(names.begin(), names.end(), out) == names.end())
    r.fail("body", "no body named " + in_quotes(out), join(names, true));
}

// A mesh's `scale`: the factor from the file's units to metres, up to a million (1e300 made a
// body of infinite volume).
Bounds mesh_scale() {
  Bounds b = greater_than(0);
  b.hi = 1e6;
  b.note = "(the factor from the file's units to metres, e.g. 0.001 for millimetres)";
  return b;
}

// A mesh file reference: `mesh` (required), `scale` and `translate`.
void parse_mesh_reference(const TableReader& r, const std::string& file, std::string& mesh,
                          std::string& mesh_path, double& scale, Vec3d& translate) {
  r.string("mesh", mesh, {}, Presence::required);
  if (mesh.empty()) r.fail("mesh", "the path is empty", "a path to an .obj, .ply or .stl file");
  mesh_path = resolve_path(file, mesh);
  r.number("scale", scale, mesh_scale());
  r.vec3("translate", translate);
}

// Shape and its dimensions: the keys of the chosen shape are required (mesh: `mesh` only),
// those of other shapes are errors.
void parse_shape(const TableReader& r, SceneBody& b, const std::string& file) {
  r.string("shape", b.shape, kShapes);
  r.string("particles", b.particles, kParticleKinds);
  const size_t s = size_t(std::find(kShapes.begin(), kShapes.end(), b.shape) - kShapes.begin());
  const Keys& own = kShapeKeys[s];
  for (std::string_view key : kDimensionKeys)
    if (r.has(key) && std::find(own.begin(), own.end(), key) == own.end())
      r.fail(key, "not a dimension of shape = " + in_quotes(b.shape),
             "for " + b.shape + ": " + join(own, false));
  const Bounds positive = greater_than(0);
  if (b.shape == "box") read_box_size(r, b.size);
  if (b.shape == "plate") {
    r.number("width", b.width, positive, Presence::required);
    r.number("depth", b.depth, positive, Presence::required);
    r.number("thickness", b.thickness, positive, Presence::required);
    b.size = {b.width, b.thickness, b.depth};
  }
  if (b.shape == "sphere" || b.shape == "cylinder" || b.shape == "torus" || b.shape == "vase")
    r.number("radius", b.radius, positive, Presence::required);
  if (b.shape == "cylinder" || b.shape == "vase") r.number("height", b.height, positive, Presence::required);
  if (b.shape == "torus") {
    Bounds tube = in_open(0, b.radius);
    tube.note = "less than radius, so the torus has a hole";
    r.number("tube_radius", b.tube_radius, tube, Presence::required);
  }
  if (b.shape == "vase") {
    // The wall must fit inside the rounded foot; a shell replaces the wall by its own thickness.
    Bounds wall = in_open(0, vase_foot(b.radius, b.height));
    wall.note = "less than the foot radius min(radius/4, height/10)";
    if (b.particles == "shell") {
      if (r.has("wall"))
        r.fail("wall", "a shell's thickness is shell_thickness", "no wall with particles = \"shell\"");
    } else {
      r.number("wall", b.wall, wall, Presence::required);
    }
  }
  if (b.shape == "mesh") {
    r.string("mesh", b.mesh, {}, Presence::required);
    if (b.mesh.empty()) r.fail("mesh", "the path is empty", "a path to an .obj, .ply or .stl file");
    b.mesh_path = resolve_path(file, b.mesh);
    r.number("scale", b.scale, mesh_scale());
    r.string("repair", b.repair, {"none", "fill_holes", "weld"});
  }
}

// TetGen and shell switches, only with the particles that use them.
void parse_particle_switches(const TableReader& r, SceneBody& b) {
  const bool tets = b.particles == "tets" || b.particles == "shell", shell = b.particles == "shell";
  for (std::string_view key : {"tet_quality", "tet_max_volume", "tet_keep_surface"})
    if (r.has(key) && !tets)
      r.fail(key, "only for particles = \"tets\" or \"shell\"",
             "no TetGen switch with particles = " + in_quotes(b.particles));
  for (std::string_view key : {"shell_thickness", "shell_layers"})
    if (r.has(key) && !shell)
      r.fail(key, "only for particles = \"shell\"",
             "no shell key with particles = " + in_quotes(b.particles));
  if (r.has("tet_quality")) {
    const Bounds quality{0, 10, false, false, kTetQualityAllowed};
    r.number("tet_quality", b.tet_quality, quality);
    if (!tet_quality_allowed(b.tet_quality))
      r.fail("tet_quality", number_text(b.tet_quality) + " is out of range", quality.describe());
  }
  double volume = 0;
  if (r.number("tet_max_volume", volume, greater_than(0))) b.tet_max_volume = volume;
  r.boolean("tet_keep_surface", b.tet_keep_surface);
  if (!shell) return;
  Bounds thickness = greater_than(0);
  if (b.shape == "vase") {
    thickness = in_open(0, vase_foot(b.radius, b.height));
    thickness.note = "less than the vase's foot radius min(radius/4, height/10)";
  }
  r.number("shell_thickness", b.shell_thickness, thickness, Presence::required);
  r.integer("shell_layers", b.shell_layers, 2, 64);
}

SceneBody parse_body(size_t index, const TableReader& r, const std::vector<SceneMaterial>& materials,
                     const std::string& file) {
  SceneBody b;
  b.name = "body" + std::to_string(index);
  // A name is printed on one line and names the body's files (`perifrac shapes`): no control
  // character, no folder separator, not empty, "." or "..".
  if (r.string("name", b.name) &&
      (b.name.empty() || b.name == "." || b.name == ".." ||
       std::any_of(b.name.begin(), b.name.end(), [](char c) { return c == '/' || (unsigned char)(c) < 32; })))
    r.fail("name", "'" + detail::printable(b.name) + "'",
           "a non-empty name without '/' or control characters, not '.' or '..'");
  parse_shape(r, b, file);
  parse_particle_switches(r, b);
  r.vec3("center", b.center);
  r.vec3("velocity", b.velocity);
  r.number("spacing", b.spacing, greater_than(0), Presence::required);
  Vec3d origin{0, 0, 0};
  if (r.vec3("lattice_origin", origin)) {
    if (b.particles != "grid")
      r.fail("lattice_origin",
             "a lattice origin places grid particles, and this body's are " + in_quotes(b.particles),
             "lattice_origin with particles = \"grid\"");
    b.lattice_origin = origin;
  }

  // The material must name a [materials.NAME] table.
  r.string("material", b.material, {}, Presence::required);
  Keys names;
  for (const SceneMaterial& m : materials) names.push_back(m.name);
  if (std::find(names.begin(), names.end(), b.material) == names.end())
    r.fail("material", "no material named " + in_quotes(b.material), join(names, true));

  // A box or plate of grid particles: round(size / spacing) per axis (host/geometry/box_grid.cpp).
  // Every axis needs at least one particle, and the body's particle count must fit an int32
  // index. Other bodies are counted when their particles are made (scene_setup.cpp).
  if ((b.shape != "box" && b.shape != "plate") || b.particles != "grid" || b.lattice_origin) return b;
  const std::string size_key = b.shape == "box" ? "size" : "width, depth, thickness";
  double count = 1;
  for (int a = 0; a < 3; ++a) {
    const double per_axis = std::round(b.size[a] / b.spacing);
    if (per_axis < 1)
      r.fail(b.shape == "box" ? "size"
                              : (a == 0   ? "width"
                                 : a == 1 ? "thickness"
                                          : "depth"),
             std::string(kAxisNames[a]) + " size " + number_text(b.size[a]) +
                 " is less than half the spacing " + number_text(b.spacing) +
                 ", which would give zero particles along that axis",
             "sizes >= spacing / 2");
    count *= per_axis;
  }
  const double max_count = std::numeric_limits<int32_t>::max();
  if (count > max_count)
    r.fail("spacing", "the body would have " + number_text(count) + " particles",
           "at most " + number_text(max_count) + " particles per body");
  return b;
}

SceneAnchor parse_anchor(const TableReader& r, const std::vector<SceneBody>& bodies) {
  SceneAnchor a;
  r.vec3("box_min", a.box_min, Presence::required);
  r.vec3("box_max", a.box_max, Presence::required);
  parse_body_name(r, a.body, bodies);
  if (r.has("velocity") && r.has("path"))
    r.fail("path", "both velocity and path are given", "either a constant velocity or a keyframed path");
  r.vec3("velocity", a.velocity);
  r.keyframes("path", a.path);
  r.vec3("angular_velocity", a.angular_velocity);
  Vec3d pivot{};
  if (r.vec3("pivot", pivot)) a.pivot = pivot;
  double release = 0;
  if (r.number("release", release, at_least(0))) a.release = release;
  for (int c = 0; c < 3; ++c) {
    if (a.box_max[c] < a.box_min[c])
      r.fail("box_max",
             std::string(kAxisNames[c]) + " (" + number_text(a.box_max[c]) + ") is below box_min's (" +
                 number_text(a.box_min[c]) + ")",
             "each component >= box_min's");
  }
  return a;
}

// A moving centre: a keyframed `path` (its first point the centre), or `center` and `velocity`.
void parse_centre_motion(const TableReader& r, const std::string& what, Vec3d& center, Vec3d& velocity,
                         std::vector<SceneKeyframe>& path) {
  if (r.keyframes("path", path)) {
    for (std::string_view key : {"center", "velocity"})
      if (r.has(key))
        r.fail(key, "a keyframed " + what + " takes its centre from path", "path, or center and velocity");
    center = {path[0][1], path[0][2], path[0][3]};
  } else {
    r.vec3("center", center, Presence::required);
    r.vec3("velocity", velocity);
  }
}

SceneProjectile parse_projectile(const TableReader& r) {
  SceneProjectile p;
  parse_centre_motion(r, "projectile", p.center, p.velocity, p.path);
  r.number("radius", p.radius, greater_than(0), Presence::required);
  r.number("strength", p.strength, at_least(0), Presence::required);
  return p;
}

SceneCollider parse_collider(const TableReader& r) {
  SceneCollider c;
  r.string("shape", c.shape, kColliderShapes, Presence::required);
  parse_centre_motion(r, "collider", c.center, c.velocity, c.path);
  if (r.vec3("axis", c.axis) && !(c.axis[0] * c.axis[0] + c.axis[1] * c.axis[1] + c.axis[2] * c.axis[2] > 0))
    r.fail("axis", "the zero vector", "a nonzero direction [x, y, z]");
  r.vec3("angular_velocity", c.angular_velocity);
  // The dimensions each shape takes, and only those.
  const bool round = c.shape == "sphere" || c.shape == "capsule" || c.shape == "cylinder";
  const bool long_ = c.shape == "capsule" || c.shape == "cylinder";
  for (std::string_view key : {"radius", "length", "size"}) {
    const bool takes =
        (key == "radius" && round) || (key == "length" && long_) || (key == "size" && c.shape == "box");
    if (r.has(key) && !takes)
      r.fail(key, "a " + c.shape + " collider has no " + std::string(key),
             c.shape == "plane"  ? "center and axis (the normal)"
             : c.shape == "mesh" ? "mesh, scale and cell"
             : c.shape == "box"  ? "size [x, y, z]"
                                 : (long_ ? "radius and length" : "radius"));
  }
  // A mesh: its file, scale and grid spacing, and only for a mesh.
  for (std::string_view key : {"mesh", "scale", "cell"})
    if (r.has(key) && c.shape != "mesh")
      r.fail(key, "a " + c.shape + " collider has no " + std::string(key),
             "mesh, scale and cell for shape = \"mesh\"");
  if (c.shape == "mesh") {
    r.string("mesh", c.mesh, {}, Presence::required);
    if (c.mesh.empty()) r.fail("mesh", "the path is empty", "a path to an .obj, .ply or .stl file");
    c.mesh_path = resolve_path(r.file(), c.mesh);
    r.number("scale", c.scale, mesh_scale());
    double cell = 0;
    if (r.number("cell", cell, greater_than(0))) c.cell = cell;
  }
  if (round) r.number("radius", c.radius, greater_than(0), Presence::required);
  if (long_) r.number("length", c.length, greater_than(0), Presence::required);
  if (c.shape == "box") read_box_size(r, c.size);
  // Free: a mass or a density (not both, not for a plane, not on a path).
  double m = 0;
  if (r.has("mass") && r.has("density"))
    r.fail("density", "both mass and density are given", "one of mass [kg] and density [kg/m^3]");
  if (r.number("mass", m, greater_than(0))) c.mass = m;
  if (r.number("density", m, greater_than(0))) c.density = m;
  if (c.mass || c.density) {
    const std::string_view key = c.mass ? "mass" : "density";
    if (c.shape == "plane")
      r.fail(key, "a plane cannot be free (it has no finite volume)",
             "a sphere, box, capsule, cylinder or mesh");
    if (!c.path.empty())
      r.fail("path", "a free collider moves as it is pushed", "velocity for its initial velocity");
  }
  r.string("law", c.law, kColliderLaws);
  if (c.law == "lammps_indent") {  // LAMMPS's fix indent: K (R - r)^2, no default K, no damping or friction
    for (std::string_view key : {"friction", "static_friction", "damping"})
      if (r.has(key))
        r.fail(key, "the lammps_indent law has no " + std::string(key),
               "shape, motion and stiffness (K [N/m^5])");
    c.damping = 0;
    double k = 0;
    r.number("stiffness", k, greater_than(0), Presence::required);
    c.stiffness = k;
  }
  double stiffness = 0;
  if (c.law == "penalty" && r.number("stiffness", stiffness, greater_than(0))) c.stiffness = stiffness;
  r.number("friction", c.friction, at_least(0));
  double static_friction = 0;
  if (r.number("static_friction", static_friction, at_least(0))) {
    if (static_friction < c.friction)
      r.fail("static_friction",
             number_text(static_friction) + " is below friction " + number_text(c.friction),
             "static_friction >= friction");
    c.static_friction = static_friction;
  }
  r.number("damping", c.damping, in_closed(0, 1));
  return c;
}

// A list of points [[x, y, z], ...] with at least `min` entries.
// An array of `min` points or more, exactly `min` with `exact`.
std::vector<Vec3d> parse_points(const TableReader& r, std::string_view key, size_t min, bool exact = false) {
  const std::string allowed =
      std::string("an array of ") + (exact ? "" : "at least ") + std::to_string(min) + " points [x, y, z]";
  const toml::node* n = r.node(key);
  if (!n) r.fail(key, "missing required key", allowed);
  const auto* a = n->as_array();
  if (!a) r.fail(key, "expected an array of points, got " + type_name(*n), allowed);
  if (a->size() < min || (exact && a->size() != min))
    r.fail(key, std::to_string(a->size()) + " point(s)", allowed);
  std::vector<Vec3d> out;
  for (size_t k = 0; k < a->size(); ++k) {
    const std::string item = r.path(key) + "[" + std::to_string(k) + "]";
    const auto* point = a->get(k)->as_array();
    if (!point || point->size() != 3) scene_error(r.file(), item, "expected [x, y, z]", allowed);
    Vec3d p{};
    for (size_t c = 0; c < 3; ++c)
      p[c] = to_number(*point->get(c), r.file(), item + "[" + std::to_string(c) + "]", Bounds{});
    out.push_back(p);
  }
  return out;
}

// A quad crack's corners span a plane (the cross product of its diagonals its normal) and lie in it,
// each within a thousandth of the longer diagonal (corners typed with a few digits pass).
void check_planar_quad(const TableReader& r, const std::array<Vec3d, 4>& q) {
  const Vec3d d0 = q[2] - q[0], d1 = q[3] - q[1];
  const double size = std::max(norm(d0), norm(d1));
  const Vec3d n = cross(d0, d1);
  if (!(norm(n) > 1e-12 * size * size))
    r.fail("corners", "a quad of no area (its diagonals are parallel)",
           "4 corners around a planar quadrilateral");
  const Vec3d unit = (1 / norm(n)) * n, centre = 0.25 * (q[0] + q[1] + q[2] + q[3]);
  for (size_t k = 0; k < 4; ++k)
    if (const double off = std::fabs(dot(q[k] - centre, unit)); off > 1e-3 * size) {
      char what[96];
      std::snprintf(what, sizeof what, "not planar: corner %zu lies %.3g m off the quad's plane", k, off);
      r.fail("corners", what, "4 corners in one plane, within 0.001 of the quad's size");
    }
}

SceneCrack parse_crack(const TableReader& r, const std::vector<SceneBody>& bodies, const std::string& file) {
  SceneCrack c;
  const size_t shape = parse_kind(r, c.shape, kCrackShapes, kCrackShapeKeys);
  Bounds strength = {0, 1, false, true, "0 removes the bonds crossing, less than 1 weakens them"};
  r.number("strength", c.strength, strength);
  parse_body_name(r, c.body, bodies);
  auto nonzero = [&](std::string_view key, const Vec3d& v) {
    if (v[0] == 0 && v[1] == 0 && v[2] == 0) r.fail(key, "the zero vector", "a non-zero [x, y, z]");
  };
  switch (shape) {
    case 0: {
      const auto corners = parse_points(r, "corners", 4, true);
      std::copy(corners.begin(), corners.end(), c.corners.begin());
      check_planar_quad(r, c.corners);
      break;
    }
    case 1:
      c.points = parse_points(r, "points", 2);
      r.vec3("extrude", c.extrude, Presence::required);
      nonzero("extrude", c.extrude);
      break;
    case 2:
      r.vec3("start", c.start, Presence::required);
      r.vec3("extrude", c.extrude, Presence::required);
      nonzero("extrude", c.extrude);
      r.number("step_length", c.step_length, greater_than(0), Presence::required);
      r.integer("walks", c.walks, 1);
      r.integer("steps", c.steps, 1);
      if (c.walks * c.steps > 100000)
        r.fail("steps", std::to_string(c.walks * c.steps) + " steps in all", "walks * steps <= 100000");
      r.number("turn", c.turn, in_closed(0, 180));
      break;
    default:
      parse_mesh_reference(r, file, c.mesh, c.mesh_path, c.scale, c.translate);
  }
  return c;
}

SceneRegion parse_region(const TableReader& r, const std::vector<SceneBody>& bodies,
                         const std::string& file) {
  SceneRegion g;
  const size_t shape = parse_kind(r, g.shape, kRegionShapes, kRegionShapeKeys);
  parse_body_name(r, g.body, bodies);
  if (shape == 0) {
    r.vec3("box_min", g.box_min, Presence::required);
    r.vec3("box_max", g.box_max, Presence::required);
    for (int c = 0; c < 3; ++c)
      if (g.box_max[size_t(c)] < g.box_min[size_t(c)])
        r.fail("box_max", std::string(kAxisNames[c]) + " is below box_min's", "each component >= box_min's");
  } else if (shape == 1) {
    r.vec3("center", g.center, Presence::required);
    r.number("radius", g.radius, greater_than(0), Presence::required);
  } else {
    parse_mesh_reference(r, file, g.mesh, g.mesh_path, g.scale, g.translate);
  }
  double limit = 0;
  if (r.number("strain_limit", limit, in_open(0, 1))) g.strain_limit = limit;
  r.number("strain_limit_factor", g.strain_limit_factor, greater_than(0));
  if (!g.strain_limit && !r.has("strain_limit_factor"))
    r.fail("", "the region changes nothing", "strain_limit in (0, 1) and/or strain_limit_factor > 0");
  return g;
}

SceneShards parse_shards(const TableReader& r, const std::vector<SceneBody>& bodies,
                         const std::string& file) {
  SceneShards g;
  r.number("size", g.size, greater_than(0), Presence::required);
  Bounds hold = in_closed(1, 255);
  hold.lo_open = true;
  hold.note = "1 would hold the cells no better than their faces";
  r.number("hold", g.hold, hold);
  r.number("jitter", g.jitter, in_closed(0, 1));
  parse_body_name(r, g.body, bodies);
  if (r.string("pattern", g.pattern)) {
    if (g.pattern.empty()) r.fail("pattern", "the path is empty", "the output folder of a finished run");
    g.pattern_path = resolve_path(file, g.pattern);
    if (r.has("radius") || r.has("center"))
      r.fail("pattern", "is given with a zone (radius, center)", "a pattern over the whole body, or a zone");
    double dust_hold = 0;
    if (r.number("dust_hold", dust_hold, in_closed(1, 255))) g.dust_hold = dust_hold;
  } else if (r.has("dust_hold")) {
    r.fail("dust_hold", "is given without pattern",
           "dust_hold together with pattern (the pattern's dust cells)");
  }
  double radius = 0;
  if (r.number("radius", radius, greater_than(0))) {
    g.radius = radius;
    r.vec3("center", g.center, Presence::required);
  } else if (r.has("center")) {
    r.fail("center", "is given without radius", "center together with radius > 0 (a zone), or neither");
  }
  return g;
}

// [render]: what `perifrac run` renders as it goes. It reads the binary frames, so output.binary
// must stay on.
SceneRender parse_render(const TableReader& r, const std::string& file, bool write_binary) {
  SceneRender s;
  std::array<double, 3> v{};
  if (r.vec3("eye", v)) s.eye = v;
  if (r.vec3("look_at", v)) s.look_at = v;
  if (s.eye && s.look_at && *s.eye == *s.look_at)
    r.fail("look_at", "equals eye", "a point other than the eye");
  r.number("vfov", s.vfov, in_open(0, 180));
  // Integers with an upper bound too.
  auto whole = [&](std::string_view key, int64_t& value, int64_t lo, int64_t hi) {
    if (r.integer(key, value, lo) && value > hi)
      r.fail(key, std::to_string(value) + " is out of range",
             "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  };
  whole("width", s.width, 16, 16384);
  whole("height", s.height, 16, 16384);
  whole("spp", s.spp, 1, 1024);
  r.string("material", s.material, {"opaque", "glass"});
  r.number("ior", s.ior, in_closed(1, 4));
  r.string("environment", s.environment);
  if (s.environment.empty())
    r.fail("environment", "the path is empty", "\"sky\" or the path of a Radiance .hdr file");
  if (s.environment != "sky") s.environment_path = resolve_path(file, s.environment);
  r.integer("every", s.every, 0);
  r.boolean("damage_colors", s.damage_colors);
  r.string("surface", s.surface, {"elements", "mesh"});
  whole("smooth_cracks", s.smooth_cracks, 0, 100);
  // [render.bodies.NAME]: a look and a colour per body (the names are checked against the bodies
  // in parse_root).
  Keys looks;
  for (const std::string& name : look_names()) looks.push_back(name);
  for (const auto& [name, body] : r.named_tables("bodies", kRenderBodyKeys)) {
    SceneBodyLook b;
    b.body = name;
    body.string("look", b.look, looks);
    std::array<double, 3> color{};
    if (body.numbers("color", color, "an array of 3 numbers [r, g, b] in [0, 1] (linear RGB)")) {
      for (double c : color)
        if (!(c >= 0 && c <= 1))
          body.fail("color", "a component is outside [0, 1]", "an array of 3 numbers [r, g, b] in [0, 1]");
      b.color = color;
    }
    if (b.look.empty() && !b.color) body.fail("", "names neither a look nor a colour", "look, color or both");
    s.bodies.push_back(b);
  }
  if (!write_binary)
    r.fail("", "needs the binary frames it renders", "output.binary = true with a [render] block");
  return s;
}

Scene parse_root(const toml::table& root, const std::string& path) {
  Scene scene;
  scene.path = path;
  const TableReader top(root, "", path, kTopKeys);

  // description: one line of free text.
  top.string("description", scene.description);
  if (scene.description.find_first_of("\r\n") != std::string::npos)
    top.fail("description", "contains a line break", "a one-line string");

  // [simulation]
  const TableReader sim = top.table("simulation", kSimulationKeys);
  std::string dt_word;
  if (sim.is_string("dt")) {
    sim.string("dt", dt_word, {"auto"});
    scene.dt_auto = true;
  } else {
    Bounds dt = at_least(1e-15);  // (below a femtosecond the clock of a long run stops advancing)
    dt.note = "(or \"auto\" for half the stable time step)";
    sim.number("dt", scene.dt, dt);
  }
  sim.integer("steps_per_frame", scene.steps_per_frame, 1, kMaxStepsPerFrame);
  sim.integer("frames", scene.frames, 0, kMaxFrames);
  int64_t seed = 0;
  if (sim.integer("seed", seed, 0)) scene.seed = static_cast<uint64_t>(seed);

  // [world]
  const TableReader world = top.table("world", kWorldKeys);
  constexpr double kMaxGravity = 1e9;  // [m/s^2] (1e8 g, past any centrifuge)
  if (world.vec3("gravity", scene.gravity) &&
      !(std::hypot(scene.gravity[0], scene.gravity[1], scene.gravity[2]) <= kMaxGravity))
    world.fail("gravity",
               "an acceleration of " +
                   number_text(std::hypot(scene.gravity[0], scene.gravity[1], scene.gravity[2])) + " m/s^2",
               "at most 1e9 m/s^2");
  world.boolean("floor", scene.floor);
  world.number("floor_height", scene.floor_height);
  world.number("restitution", scene.restitution, in_closed(0, 1));

  // [contact]
  const TableReader contact = top.table("contact", kContactKeys);
  contact.boolean("enabled", scene.contact);
  contact.number("stiffness", scene.contact_stiffness, at_least(0));

  // [materials.NAME], at least one.
  for (const auto& [name, reader] : top.named_tables("materials", kMaterialKeys))
    scene.materials.push_back(parse_material(name, reader));
  if (scene.materials.empty())
    top.fail("materials", "no material is defined", "at least one [materials.NAME] table");

  // [[bodies]], at least one; they refer to the materials.
  const auto bodies = top.table_array("bodies", kBodyKeys);
  for (size_t i = 0; i < bodies.size(); ++i)
    scene.bodies.push_back(parse_body(i, bodies[i], scene.materials, path));
  if (scene.bodies.empty()) top.fail("bodies", "no body is defined", "at least one [[bodies]] table");

  // [[anchors]], at most kMaxAnchors (the kernels hold their motions in a fixed array).
  const auto anchors = top.table_array("anchors", kAnchorKeys);
  if (anchors.size() > static_cast<size_t>(kMaxAnchors))
    top.fail("anchors", std::to_string(anchors.size()) + " anchors",
             "at most " + std::to_string(kMaxAnchors));
  for (const TableReader& r : anchors) scene.anchors.push_back(parse_anchor(r, scene.bodies));

  // [[projectiles]], at most kMaxProjectiles (the kernels hold them in a fixed array).
  const auto projectiles = top.table_array("projectiles", kProjectileKeys);
  if (projectiles.size() > static_cast<size_t>(kMaxProjectiles))
    top.fail("projectiles", std::to_string(projectiles.size()) + " projectiles",
             "at most " + std::to_string(kMaxProjectiles));
  for (const TableReader& r : projectiles) scene.projectiles.push_back(parse_projectile(r));
  // [[colliders]], at most kMaxColliders.
  const auto colliders = top.table_array("colliders", kColliderKeys);
  if (colliders.size() > static_cast<size_t>(kMaxColliders))
    top.fail("colliders", std::to_string(colliders.size()) + " colliders",
             "at most " + std::to_string(kMaxColliders));
  for (const TableReader& r : colliders) scene.colliders.push_back(parse_collider(r));

  // [[cracks]] and [[regions]]
  for (const TableReader& r : top.table_array("cracks", kCrackKeys))
    scene.cracks.push_back(parse_crack(r, scene.bodies, path));
  for (const TableReader& r : top.table_array("regions", kRegionKeys))
    scene.regions.push_back(parse_region(r, scene.bodies, path));
  // [[shards]]: at most one table per body.
  for (const TableReader& r : top.table_array("shards", kShardKeys)) {
    const SceneShards g = parse_shards(r, scene.bodies, path);
    for (const SceneShards& e : scene.shards)
      if (e.body.empty() || g.body.empty() || e.body == g.body)
        r.fail("body",
               g.body.empty() ? "every body, but an earlier [[shards]] names one already"
                              : "'" + g.body + "' has an earlier [[shards]] already",
               "one [[shards]] per body (a table without `body` is for every body)");
    scene.shards.push_back(g);
  }

  // [output]
  const TableReader output = top.table("output", kOutputKeys);
  output.boolean("vtk", scene.write_vtk);
  output.boolean("binary", scene.write_binary);

  // [render]
  if (top.has("render"))
    scene.render = parse_render(top.table("render", kRenderKeys), path, scene.write_binary);
  if (scene.render) {
    Keys names;
    for (const SceneBody& b : scene.bodies) names.push_back(b.name);
    for (const SceneBodyLook& l : scene.render->bodies)
      if (std::find(names.begin(), names.end(), l.body) == names.end())
        scene_error(path, "render.bodies." + l.body, "no body is named " + in_quotes(l.body),
                    join(names, true));
  }
  return scene;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& path,
                  const std::vector<std::string>& overrides) {
  toml::table root = parse_toml_document(text, path);
  for (const std::string& setting : overrides) apply_override(root, setting, path);
  return parse_root(root, path);
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::string why;  // (a regular file within the input limit, host/io/input_file.h)
  const std::optional<std::string> text = read_input_file(path, why);
  if (!text) throw SceneError(path, "", "cannot read scene file: " + why);
  return parse_scene(*text, path, overrides);
}

}  // namespace pd
