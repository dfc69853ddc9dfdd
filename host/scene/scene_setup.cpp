#include "host/scene/scene_setup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <limits>
#include <optional>
#include <string>

#include "cuda/engine/bond_cuts.h"
#include "cuda/engine/material.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/engine/surface_ghosts.h"
#include "cuda/parallel/comm.h"
#include "host/geometry/box_grid.h"
#include "host/geometry/grid_particles.h"
#include "host/geometry/inside_test.h"
#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/random.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tet_body_solids.h"
#include "host/geometry/tet_particles.h"
#include "host/geometry/tetgen.h"
#include "host/geometry/voronoi_particles.h"
#include "host/scene/collider_setup.h"
#include "host/scene/range_checks.h"
#include "host/scene/scene_cracks.h"
#include "host/scene/scene_smells.h"

namespace pd {

namespace {

Vec3 to_vec3(const Vec3d& v) {
  return {real(v[0]), real(v[1]), real(v[2])};
}

bool inside(const SceneAnchor& a, Vec3 x) {
  return x.x >= a.box_min[0] && x.x <= a.box_max[0] && x.y >= a.box_min[1] && x.y <= a.box_max[1] &&
         x.z >= a.box_min[2] && x.z <= a.box_max[2];
}

// The host-side script of an anchor: its pivot defaults to the centre of its box.
AnchorScript anchor_script(const SceneAnchor& a) {
  AnchorScript s;
  for (int c = 0; c < 3; ++c)
    s.pivot[size_t(c)] =
        a.pivot ? (*a.pivot)[size_t(c)] : 0.5 * (a.box_min[size_t(c)] + a.box_max[size_t(c)]);
  s.velocity = a.velocity;
  s.path = a.path;
  s.omega = a.angular_velocity;
  if (a.release) s.release = *a.release;
  return s;
}

// Initial velocity of a particle at rest position x held by anchor script s: a path's is that of
// its segment leaving t = 0 (sample_path gives none at a keyframe's time), so that frame 0's
// kinetic energy is the motion the path starts with.
Vec3 anchor_velocity(const AnchorScript& s, Vec3 x) {
  std::array<double, 3> start = s.velocity;
  if (!s.path.empty()) {
    start = {0, 0, 0};
    for (size_t k = 0; k + 1 < s.path.size(); ++k)
      if (s.path[k][0] <= 0 && 0 < s.path[k + 1][0])
        for (int c = 0; c < 3; ++c)
          start[size_t(c)] = (s.path[k + 1][c + 1] - s.path[k][c + 1]) / (s.path[k + 1][0] - s.path[k][0]);
  }
  const Vec3 omega = to_vec3(s.omega), d = x - to_vec3(s.pivot);
  return to_vec3(start) + cross(omega, d);
}

// Kernel constants of one body's material at the body's spacing.
// `spacing` is lambda, the particle spacing the horizon is measured in; `contact_spacing` sets
// the contact distance (a quarter of it per particle).
Material derive_material(const SceneMaterial& sm, double spacing, double contact_spacing,
                         MaterialSummary& summary) {
  const double delta = sm.horizon * spacing;
  const bool state = sm.model == "state_based";
  Material m;
  m.model = state ? kStateBased : kBondBased;
  m.horizon = real(delta);
  m.spacing = real(spacing);
  m.compression_alpha = real(sm.compression_alpha);
  m.partial_volumes = sm.partial_volumes.value_or(state) ? 1 : 0;
  m.contact_spacing = real(contact_spacing);
  m.damage_alpha = real(sm.damage_alpha);
  summary.spacing = spacing;
  summary.horizon = delta;
  if (!state) {
    const double c = pmb_lattice_micromodulus(sm.bulk_modulus, m);
    m.micromodulus = real(c);
    m.surface_correction = sm.surface_correction.value_or(!sm.surface_ghosts) ? 1 : 0;
    m.ghost_correction = sm.surface_ghosts ? 1 : 0;
    m.axial_sum = real(lattice_family_sums(m).axial_sum);
    summary.micromodulus = m.micromodulus;
    summary.strain_limit =
        sm.strain_limit ? *sm.strain_limit : pmb_lattice_critical_stretch(*sm.fracture_energy, c, m);
    summary.critical_dt = pmb_critical_time_step(sm.density, sm.bulk_modulus, delta);
    return m;
  }
  m.bulk_modulus = real(sm.bulk_modulus);
  m.shear_modulus = real(sm.shear_modulus);
  m.surface_correction = sm.surface_correction.value_or(false) ? 1 : 0;
  m.ghost_correction = sm.surface_ghosts ? 1 : 0;
  m.axial_sum = real(lattice_family_sums(m).bond_sum / 3);  // the second moment's, per axis
  m.chen_fracture = sm.fracture == "chen" ? 1 : 0;
  if (sm.plastic) {
    m.plastic = 1;
    m.yield_psi0 =
        real(sm.plastic->yield_stress ? yield_psi0(*sm.plastic->yield_stress, delta) : sm.plastic->psi0);
    m.plastic_limit = real(sm.plastic->limit);
  }
  if (sm.anisotropy) {
    m.anisotropic = 1;
    for (int k = 0; k < 9; ++k) m.aniso[k] = real(sm.anisotropy->matrix[k]);
  }
  summary.strain_limit =
      sm.strain_limit ? *sm.strain_limit
                      : lps_critical_stretch(*sm.fracture_energy, sm.bulk_modulus, sm.shear_modulus, delta);
  summary.critical_dt = lps_critical_time_step(sm.density, sm.bulk_modulus, sm.shear_modulus, delta);
  return m;
}

// Particles of one body at `spacing`: the box grid of box and plate bodies (the layout of
// box_grid.h), else grid, tet, fattened-shell or Voronoi particles of the body's solid.
// Grid particles on the body's lattice (`lattice_origin`): the lattice points inside its shape,
// the surface included (a millionth of a spacing of slack), analytic for a box, plate, sphere or
// cylinder, else by the solid's inside test.
ParticleGeometry body_lattice_particles(const SceneBody& body, double spacing, int64_t max_particles,
                                        const std::string& key) {
  const Vec3d c = body.center, h = 0.5 * body.size;
  const double slack = 1e-6 * spacing, r = body.radius + slack;
  const std::string name = body.shape == "mesh" ? body.mesh_path : key;
  auto lattice = [&](const Box3d& box, const std::function<bool(const Vec3d&)>& inside) {
    return lattice_particles(box, *body.lattice_origin, spacing, inside, max_particles, name);
  };
  if (body.shape == "box" || body.shape == "plate")
    return lattice({c - h, c + h}, [&](const Vec3d& p) {
      for (int a = 0; a < 3; ++a)
        if (std::abs(p[size_t(a)] - c[size_t(a)]) > h[size_t(a)] + slack) return false;
      return true;
    });
  if (body.shape == "sphere")
    return lattice({c - Vec3d{r, r, r}, c + Vec3d{r, r, r}},
                   [&](const Vec3d& p) { return distance2(p, c) <= r * r; });
  if (body.shape == "cylinder") {
    const double half = 0.5 * body.height + slack;
    return lattice({c - Vec3d{r, half, r}, c + Vec3d{r, half, r}}, [&](const Vec3d& p) {
      const double x = p[0] - c[0], z = p[2] - c[2];
      return x * x + z * z <= r * r && std::abs(p[1] - c[1]) <= half;
    });
  }
  const TriMesh solid = body_solid(body, body_solid_edge(body, spacing), key);
  const InsideTest inside(solid);
  return lattice(bounds(solid), [&](const Vec3d& p) { return inside.inside(p); });
}

// The limit is asked for before the particles are made, but for tets once TetGen has started.
ParticleGeometry body_particles(const SceneBody& body, double spacing, double spacing_factor, uint64_t seed,
                                const ParticleLimit& max_particles, const std::string& key) {
  if (body.lattice_origin) return body_lattice_particles(body, spacing, max_particles(), key);
  if ((body.shape == "box" || body.shape == "plate") && body.particles == "grid")
    return box_grid_particles(body.center, body.size, spacing);
  const TriMesh solid = body_solid(body, body_solid_edge(body, spacing), key);
  const std::string name = body.shape == "mesh" ? body.mesh_path : key;
  if (body.particles == "grid") return grid_particles(solid, spacing, max_particles(), name);
  if (body.particles == "voronoi") return voronoi_particles(solid, spacing, seed, max_particles(), name);
  TetgenOptions options;
  options.quality = body.tet_quality;
  options.keep_surface = body.tet_keep_surface;
  const double cube = spacing_factor * spacing_factor * spacing_factor;
  options.max_volume = body.tet_max_volume ? *body.tet_max_volume * cube : 2 * spacing * spacing * spacing;
  if (body.particles == "tets") return tet_particles(solid, options, max_particles, name);
  return shell_particles(solid, body.shell_thickness,
                         scaled_shell_layers(int(body.shell_layers), spacing_factor), options, max_particles,
                         name);
}

// Per-particle strain limit: normal scatter of relative deviation sigma, truncated at 3 sigma
// and kept above 5% of the mean so no bond starts out broken.
real scattered_limit(double tau, double sigma, Random& rng) {
  const double z = std::fmax(-3.0, std::fmin(3.0, rng.normal()));
  return real(tau * std::fmax(0.05, 1.0 + sigma * z));
}

// Elements whose shared face a pre-crack cuts are not adjacent: the engine removes the bond
// between their particles (the same test on the same positions), so fragments and crack meshes
// see a crack there from the start.
void remove_cut_pairs(const std::vector<CutTriangle>& cuts, const ParticleSet& ps,
                      std::vector<std::pair<int32_t, int32_t>>& pairs) {
  if (cuts.empty() || pairs.empty()) return;
  double reach = 0;
  for (const auto& [a, b] : pairs)
    reach = std::max(reach, double(length(ps.rest[size_t(a)] - ps.rest[size_t(b)])));
  const CutTester tester(cuts, 1.001 * reach, ps.rest);
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                             [&](const std::pair<int32_t, int32_t>& p) {
                               return tester.strength(p.first, ps.rest[size_t(p.first)], p.second,
                                                      ps.rest[size_t(p.second)],
                                                      ps.body[size_t(p.first)]) <= 0;
                             }),
              pairs.end());
}

}  // namespace

const SceneMaterial& find_material(const Scene& scene, const std::string& name) {
  for (const auto& m : scene.materials)
    if (m.name == name) return m;
  throw std::logic_error("material '" + name + "' was not checked by the scene loader");
}

TriMesh body_solid(const SceneBody& body, double edge, const std::string& key) {
  TriMesh mesh;
  if (body.shape == "box") mesh = box_mesh(body.size);
  if (body.shape == "plate") mesh = box_mesh({body.width, body.thickness, body.depth});
  if (body.shape == "sphere") mesh = sphere_mesh(body.radius, edge);
  if (body.shape == "cylinder") mesh = cylinder_mesh(body.radius, body.height, edge);
  if (body.shape == "torus") mesh = torus_mesh(body.radius, body.tube_radius, edge);
  if (body.shape == "vase")
    mesh = body_solid_is_sheet(body) ? vase_sheet(body.radius, body.height, edge)
                                     : vase_mesh(body.radius, body.height, body.wall, edge);
  if (body.shape == "mesh") {
    mesh = read_mesh(body.mesh_path);
    const MeshReport report =
        check_solid(mesh, body.mesh_path, {body.repair == "fill_holes", true, body.repair == "weld"});
    for (const std::string& note : report.notes)
      std::fprintf(stderr, "note: %s.mesh: %s: %s\n", key.c_str(), body.mesh_path.c_str(), note.c_str());
    transform(mesh, body.scale, {0, 0, 0});
    transform(mesh, 1, -1.0 * bounds(mesh).center());
  }
  transform(mesh, 1, body.center);
  return mesh;
}

bool body_solid_is_sheet(const SceneBody& body) {
  return body.shape == "vase" && body.particles == "shell";
}

double body_solid_edge(const SceneBody& body, double spacing) {
  const bool tets = body.particles == "tets" || body.particles == "shell";
  return tets ? 2 * spacing : spacing;
}

std::string tet_count_warning(size_t tets, double volume, double spacing, bool keep_surface,
                              const std::string& key) {
  const double grid = volume / (spacing * spacing * spacing), ratio = double(tets) / grid;
  char text[512] = "";
  if (ratio > 10)
    std::snprintf(
        text, sizeof text,
        "%s: TetGen made %zu tets, %.0f times the %.0f a grid at spacing %.3g m holds: it keeps every "
        "vertex of the surface, whose triangles are finer than the spacing (a coarser mesh, or "
        "particles = \"voronoi\", follows the spacing)",
        key.c_str(), tets, ratio, grid, spacing);
  if (ratio < 0.1)
    std::snprintf(
        text, sizeof text, "%s: TetGen made %zu tets, a %.0fth of the %.0f a grid at spacing %.3g m holds%s",
        key.c_str(), tets, 1 / ratio, grid, spacing,
        keep_surface ? ": tet_keep_surface = true keeps the surface's triangles, which are coarser than "
                       "the spacing (false lets TetGen split them)"
                     : "");
  return text;
}

// How far from the origin, in spacings, a body may reach (float positions: 1e5 spacings out their
// rounding is 1% of a spacing).
constexpr double kMaxSpacingsFromOrigin = 1e5;

SetupResult setup_scene(const Scene& scene, const SetupOptions& options) {
  if (!(options.scale > 0) || !std::isfinite(options.scale) || options.scale > 1e3)
    throw SceneError(scene.path, "--scale",
                     "must be a number in (0, 1000], got " + std::to_string(options.scale));
  SetupResult result;
  StageClock clock(&result.stages);
  SimulationInput& in = result.input;
  ParticleSet& ps = in.particles;
  Random rng(scene.seed);
  const double spacing_factor = 1.0 / std::cbrt(options.scale);
  for (const SceneAnchor& a : scene.anchors) in.motion.anchors.push_back(anchor_script(a));
  in.cuts = crack_triangles(scene);
  const auto regions = region_tests(scene);
  std::vector<int64_t> region_particles(regions.size(), 0);

  // The particle budget, taken where first needed (a pending one is found beside the first tet
  // body's TetGen: setup_options_later).
  std::optional<ParticleBudget> found;
  const auto budget_now = [&]() -> const ParticleBudget& {
    if (!found)
      found = options.pending_budget.valid() ? options.pending_budget.get()
                                             : ParticleBudget{options.max_particles, options.budget_why};
    return *found;
  };
  const auto max_now = [&] { return std::min(kMaxSceneParticles, budget_now().max_particles); };

  // Bodies: one material table entry per body (a material's horizon depends on the spacing).
  int64_t total = 0;
  std::vector<std::pair<int32_t, int32_t>> adjacency_pairs;
  auto tet_solids = std::make_shared<TetBodySolids>();  // the ghost correction's tet bodies
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const SceneBody& body = scene.bodies[b];
    const std::string key = "bodies[" + std::to_string(b) + "]";
    if (in.materials.count >= kMaxMaterials)
      throw SceneError(scene.path, key,
                       "too many bodies (allowed: at most " + std::to_string(kMaxMaterials) + ")");
    const double spacing = body.spacing * spacing_factor;
    auto too_many = [&](int64_t count) {
      const int64_t budget = max_now();
      const std::string& why = budget_now().why;
      return SceneError(scene.path, key + ".spacing",
                        "the scene would have " + std::to_string(count) + " particles (allowed: at most " +
                            std::to_string(budget) +
                            (why.empty() || budget == kMaxSceneParticles ? std::string() : ", " + why) +
                            "; use a larger spacing or a smaller --scale)");
    };
    if ((body.shape == "box" || body.shape == "plate") && body.particles == "grid") {
      // Every axis at least half a (scaled) spacing long, as the scene loader checks unscaled
      // (box_grid_counts would make one particle of the whole extent along it).
      const double smallest = *std::min_element(body.size.begin(), body.size.end());
      if (std::round(smallest / spacing) < 1) {
        char text[256];
        std::snprintf(text, sizeof text,
                      "at this scale the spacing is %.3g m, more than twice the body's smallest size %.3g m: "
                      "it would be particles as large as the body (allowed: --scale %.3g or more)",
                      spacing, smallest, std::pow(body.spacing / (2 * smallest), 3) * 1.0001);
        throw SceneError(scene.path, "--scale", text);
      }
      // Counted before the particles are made.
      const auto n = box_grid_counts(body.size, spacing);
      if (total + n[0] * n[1] * n[2] > max_now()) throw too_many(total + n[0] * n[1] * n[2]);
    }
    ParticleGeometry geometry;
    try {
      geometry = body_particles(body, spacing, spacing_factor, scene.seed + b,
                                ParticleLimit([&] { return max_now() - total; }), key);
    } catch (const MeshError& e) {
      const bool from_file = body.shape == "mesh" && e.path() == body.mesh_path;
      const bool repaired = from_file && body.repair == "fill_holes" &&  // TetGen refused the surface
                            std::string(e.what()).find(kTetgenAllowed) != std::string::npos;
      throw SceneError(
          scene.path, key + (from_file ? ".mesh" : ".particles"),
          e.what() + std::string(repaired ? "; the mesh's holes were filled (repair = \"fill_holes\"), "
                                            "and a filling may cross the surface around it"
                                          : ""));
    } catch (const ShellThicknessError& e) {
      throw SceneError(scene.path, key + ".shell_thickness", e.what());
    }
    if (geometry.size() == 0) {  // (a box says so when counted; a sphere or a mesh finds it here)
      char text[96];
      std::snprintf(text, sizeof text, "the body holds no particle at a spacing of %.3g m", spacing);
      throw SceneError(
          scene.path, key + ".spacing",
          std::string(text) + " (allowed: a spacing smaller than the body, or a larger --scale)");
    }
    if (body.particles == "tets") {
      const std::string warning =
          tet_count_warning(geometry.size(), geometry.total_volume(), spacing, body.tet_keep_surface, key);
      if (!warning.empty()) std::fprintf(stderr, "warning: %s\n", warning.c_str());
    }
    // The body's particle build: its own stages, and what they leave out (the solid, the shell).
    clock.lap(key + " particles");
    split_last_stage(result.stages, geometry.stages, key + " ", key + " solid");
    total += int64_t(geometry.size());
    if (total > max_now()) throw too_many(total);

    const SceneMaterial& sm = find_material(scene, body.material);
    if (b > 0 && sm.model != find_material(scene, scene.bodies[0].material).model)
      throw SceneError(scene.path, key + ".material",
                       "material '" + sm.name + "' is " + sm.model + " but the first body's is " +
                           find_material(scene, scene.bodies[0].material).model +
                           " (allowed: one material model per scene)");
    MaterialSummary summary;
    summary.name = sm.name;
    summary.body = body.name;
    const uint16_t mat = uint16_t(in.materials.count);
    // Levine's lambda: for grid cubes the spacing; for tets and Voronoi cells the particles'
    // typical nearest-neighbour distance (the median) sets the horizon, and their smallest
    // distance the contact distance, so a body never collides with itself at rest.
    const bool cubes = geometry.kind == ElementKind::cube;
    const double lambda = cubes ? spacing : median_nearest_distance(geometry);
    // Positions are floats: 1e5 spacings from the origin they are a spacing's 1% off, and the
    // families change (a lattice 1e6 spacings out gains a fifth of its bonds).
    double farthest = 0;
    for (const Vec3d& x : geometry.position)
      farthest = std::max({farthest, std::fabs(x[0]), std::fabs(x[1]), std::fabs(x[2])});
    if (farthest > kMaxSpacingsFromOrigin * lambda) {
      char text[160];
      std::snprintf(text, sizeof text, "the body reaches %.3g m from the origin, %.3g of its spacings",
                    farthest, farthest / lambda);
      throw SceneError(scene.path, key + ".center",
                       std::string(text) +
                           " (allowed: at most 1e5 spacings, where float positions still "
                           "hold the particles' spacing; move the scene to the origin)");
    }
    in.materials.m[in.materials.count++] =
        derive_material(sm, lambda, cubes ? spacing : geometry.min_distance, summary);
    result.critical_dt = b == 0 ? summary.critical_dt : std::fmin(result.critical_dt, summary.critical_dt);
    result.materials.push_back(summary);
    result.body_names.push_back(body.name);

    // Element adjacency, renumbered into the scene's particle indices.
    const int32_t base = int32_t(ps.size());
    for (size_t i = 0; i < geometry.size(); ++i)
      for (int64_t k = geometry.adjacency.offset[i]; k < geometry.adjacency.offset[i + 1]; ++k)
        if (int32_t(i) < geometry.adjacency.neighbor[size_t(k)])
          adjacency_pairs.emplace_back(base + int32_t(i), base + geometry.adjacency.neighbor[size_t(k)]);
    result.all_cubes = result.all_cubes && geometry.kind == ElementKind::cube;
    if (geometry.kind == ElementKind::tet) {
      result.embedded.append(geometry.tets, base);
      if (in.materials.m[mat].ghost_correction) tet_solids->add(int32_t(b), geometry.tets);
    }

    // Particles: volume from the element, mass = density x volume; anchors by rest position
    // (the last anchor holding a particle wins).
    for (size_t i = 0; i < geometry.size(); ++i) {
      const Vec3 x = to_vec3(geometry.position[i]);
      uint8_t flags = 0, group = 0;
      Vec3 v = to_vec3(body.velocity);
      for (size_t g = 0; g < scene.anchors.size(); ++g) {
        const SceneAnchor& a = scene.anchors[g];
        if (!inside(a, x) || (!a.body.empty() && a.body != body.name)) continue;
        flags |= kAnchored;
        group = uint8_t(g);
        v = anchor_velocity(in.motion.anchors[g], x);
      }
      // Regions: the last one giving a strain limit sets the base value, every factor multiplies.
      double base = summary.strain_limit, factor = 1;
      for (size_t r = 0; r < regions.size(); ++r) {
        const SceneRegion& region = scene.regions[r];
        if ((!region.body.empty() && region.body != body.name) || !regions[r](geometry.position[i])) continue;
        ++region_particles[r];
        if (region.strain_limit) base = *region.strain_limit;
        factor *= region.strain_limit_factor;
      }
      const real tau = real(factor) * scattered_limit(base, sm.strain_limit_scatter, rng);
      ps.add(x, v, real(geometry.volume[i]), real(sm.density * geometry.volume[i]), tau, mat, int32_t(b),
             flags, group);
    }
    if (geometry.kind == ElementKind::voronoi) result.voronoi.push_back({base, std::move(geometry)});
    clock.lap(key + " particle table");
  }

  for (size_t r = 0; r < region_particles.size(); ++r)  // (as an anchor that holds none is told)
    if (region_particles[r] == 0)
      std::fprintf(stderr, "warning: regions[%zu]: it holds no particle%s, so it does nothing\n", r,
                   scene.regions[r].body.empty() ? "" : (" of body '" + scene.regions[r].body + "'").c_str());
  if (!tet_solids->empty()) in.body_solids = std::move(tet_solids);
  result.shards = assign_shards(scene, ps, in.materials);
  for (const auto& [body_material, zone_material] : result.shards.zone_materials)
    copy_material_summary(result.materials, body_material, zone_material, " (shards zone)");
  remove_cut_pairs(in.cuts, ps, adjacency_pairs);
  result.adjacency = adjacency_from_pairs(ps.size(), std::move(adjacency_pairs));

  // Colliders (host/scene/collider_setup.h); their push enters every particle's stable step.
  result.collider_meshes = add_colliders(scene, in);
  result.started_in_colliders = warn_of_particles_inside_colliders(in, result.body_names);
  for (const std::string& warning : scene_smells(scene, in, result.body_names))
    std::fprintf(stderr, "%s\n", warning.c_str());
  check_physical_ranges(scene, result);
  std::vector<double> material_dt;
  for (const MaterialSummary& m : result.materials) material_dt.push_back(m.critical_dt);
  const double collider_dt = colliders_critical_dt(in, material_dt);
  if (!(collider_dt >= 1e-15)) {  // (the scene key dt's lower bound: a clock that no longer advances)
    char text[64];
    std::snprintf(text, sizeof text, "%.3g", collider_dt);
    throw SceneError(
        scene.path, "colliders",
        std::string("the colliders' contact makes the stable time step ") + text +
            " s (allowed: a collider stiffness, speed and mass that keep it at 1e-15 s or more)");
  }
  result.critical_dt = std::fmin(result.critical_dt, collider_dt);

  // Step parameters.
  StepParams& sp = in.step;
  const bool ghosts = std::any_of(scene.materials.begin(), scene.materials.end(),
                                  [](const SceneMaterial& m) { return m.surface_ghosts; });
  const double auto_fraction = kAutoDtFraction * (ghosts ? kGhostStableStepRatio : 1.0);
  result.dt = scene.dt_auto ? auto_fraction * result.critical_dt : scene.dt;
  sp.dt = real(result.dt);
  sp.gravity = to_vec3(scene.gravity);
  sp.floor_enabled = scene.floor ? 1 : 0;
  sp.floor_height = real(scene.floor_height);
  sp.restitution = real(scene.restitution);
  sp.contact_stiffness = real(scene.contact_stiffness);
  sp.n_projectiles = int32_t(scene.projectiles.size());
  for (size_t k = 0; k < scene.projectiles.size() && k < size_t(kMaxProjectiles); ++k) {
    const auto& p = scene.projectiles[k];
    // Eq. 7 is a force per particle: at --scale S every particle holds 1/S times the volume, so
    // K_S / S keeps the push per unit of mass, and the look, what it is at full size.
    sp.projectile[k] = {to_vec3(p.center), to_vec3(p.velocity), real(p.radius),
                        real(p.strength / options.scale)};
    in.motion.projectiles.push_back(p.path);
  }
  in.contact = scene.contact;
  clock.lap("shards, colliders and checks");
  return result;
}

void copy_material_summary(std::vector<MaterialSummary>& materials, uint16_t from, uint16_t to,
                           const std::string& suffix) {
  materials.resize(std::max(materials.size(), size_t(to) + 1));
  materials[to] = materials[from];
  materials[to].body += suffix;
}

namespace {

// The budget of a run of `scene` on `backend` (setup_options_for).
ParticleBudget scene_budget(const Scene& scene, Backend backend) {
  double horizon = 1;
  bool plastic = false, surface = false;
  for (const SceneMaterial& m : scene.materials) {
    horizon = std::max(horizon, m.horizon);
    plastic = plastic || m.plastic.has_value();
    surface = surface || m.surface_correction.value_or(m.model == "bond_based");
  }
  const auto world = world_comm();  // a run split over MPI ranks budgets per rank
  return world ? particle_budget(backend, horizon, plastic, surface, world->size(), world->local_size())
               : particle_budget(backend, horizon, plastic, surface);
}

}  // namespace

SetupOptions setup_options_for(const Scene& scene, double scale, Backend backend) {
  const ParticleBudget budget = scene_budget(scene, backend);
  SetupOptions o(scale);
  o.max_particles = budget.max_particles;
  o.budget_why = budget.why;
  return o;
}

SetupOptions setup_options_later(const Scene& scene, double scale, std::shared_future<Backend> backend) {
  SetupOptions o(scale);
  o.pending_budget = std::async(std::launch::async, [&scene, backend] {
                       return scene_budget(scene, backend.get());
                     }).share();
  return o;
}

}  // namespace pd
