// Turns a validated scene into particles and kernel parameters for an engine.
#pragma once

#include <future>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/engine/particle_set.h"
#include "host/fragments/embedded_mesh.h"
#include "host/geometry/element_adjacency.h"
#include "host/geometry/particle_geometry.h"
#include "host/geometry/stage_time.h"
#include "host/geometry/tri_mesh.h"
#include "host/scene/scene.h"
#include "host/scene/scene_shards.h"

namespace pd {

// dt = "auto" takes this fraction of the stable time step estimate.
constexpr double kAutoDtFraction = 0.5;

// Particle indices are int32 and some kernels form 2 i: the hard limit of a scene.
constexpr int64_t kMaxSceneParticles = 1073741823;

struct SetupOptions {
  SetupOptions(double scale_factor = 1.0) : scale(scale_factor) {}  // NOLINT: {scale} reads well
  // Multiplies every body's particle count (approximately): spacing is divided by
  // cbrt(scale). Lets a CPU run a small version of a GPU scene.
  double scale = 1.0;
  // Particle budget (memory_budget.h): a scene over it is refused before its particles are
  // made, with `budget_why` saying where the limit comes from.
  int64_t max_particles = kMaxSceneParticles;
  std::string budget_why;
  // A budget still being found (setup_options_later): where valid, setup_scene takes the budget
  // from it where first needed instead of the two fields above.
  std::shared_future<ParticleBudget> pending_budget;
};

// What the setup derived, for the start-up report.
struct MaterialSummary {
  std::string name;
  std::string body;
  double spacing = 0, horizon = 0, micromodulus = 0, strain_limit = 0, critical_dt = 0;
};

// A Voronoi body's particle geometry (cells, surface), kept for the renderer's trimtopes.
struct VoronoiBody {
  int32_t first_particle = 0;  // index of its first particle in the scene
  ParticleGeometry geometry;
};

struct SetupResult {
  SimulationInput input;
  std::vector<MaterialSummary> materials;  // one per material table entry
  std::vector<std::string> body_names;
  double critical_dt = 0;            // smallest over the materials
  int64_t started_in_colliders = 0;  // particles that start inside or pressed into a collider (warned)
  double dt = 0;               // the time step the run uses: the scene's, or kAutoDtFraction * critical_dt
  ElementAdjacency adjacency;  // which particles' elements share a face, over all bodies
  bool all_cubes = true;       // every body is made of grid cubes
  EmbeddedTets embedded;  // the tet meshes of the tet and shell bodies (Chen sec. 5.2), tets as particles
  std::vector<VoronoiBody> voronoi;      // the Voronoi bodies
  std::vector<TriMesh> collider_meshes;  // per collider: a mesh collider's surface in its frame, else empty
  ShardReport shards;                    // [[shards]]: cells made (scene_shards.h)
  ShardsPatternReport pattern;           // [[shards]] patterns, once applied (host/app/shards_pattern.h)
  std::vector<StageTime> stages;         // wall time of the set-up's stages, in order
};

// The [materials.NAME] table of `name` (checked by the scene loader to exist).
const SceneMaterial& find_material(const Scene& scene, const std::string& name);

// Throws SceneError for problems that only show once sizes are known (too many particles,
// too many material/spacing combinations, a scale out of range).
SetupResult setup_scene(const Scene& scene, const SetupOptions& options);

// The solid of a body, placed with its bounding-box centre at `center`: its procedural shape with
// about one vertex per `edge` on curved surfaces, or its mesh file, checked (and repaired as the
// scene asks; notes go to stderr under `key`, e.g. "bodies[0]"). Throws MeshError for a bad file.
TriMesh body_solid(const SceneBody& body, double edge, const std::string& key);

// Whether body_solid gives an open sheet, not a closed solid: a vase of fattened-shell particles
// (its outer surface; the shell grows inward from it).
bool body_solid_is_sheet(const SceneBody& body);

// The edge a body's solid is meshed at for particles of `spacing`: the spacing, twice it for tet
// and shell bodies (a tet is about twice the spacing on a side).
double body_solid_edge(const SceneBody& body, double spacing);

// TetGen keeps every vertex of the surface it is given (and, with tet_keep_surface, every
// triangle): a mesh much finer or coarser than the spacing gives far more (10x) or fewer (a tenth)
// tets than a grid at the spacing would hold, and with them another time step. The warning that
// says so for the body `key` (without "warning: "), or "" for a count within those bounds.
std::string tet_count_warning(size_t tets, double volume, double spacing, bool keep_surface,
                              const std::string& key);

// Entry `to` of `materials` becomes a copy of entry `from`, its body named with `suffix` added: the
// summary of a material table entry copied for part of a body (copy_material_entry).
void copy_material_summary(std::vector<MaterialSummary>& materials, uint16_t from, uint16_t to,
                           const std::string& suffix);

// Options for a run on `backend`: the particle budget (memory_budget.h) follows from the
// machine's free memory, the largest horizon and whether a material is plastic.
SetupOptions setup_options_for(const Scene& scene, double scale, Backend backend);
// The same, the backend and the budget found on a thread of their own (on a GPU the probe starts
// its driver, 0.2-0.3 s) while the set-up goes on, and waited for where first needed: for a tet
// body once its TetGen has started. `scene` must outlive the options.
SetupOptions setup_options_later(const Scene& scene, double scale, std::shared_future<Backend> backend);

}  // namespace pd
