#include "host/app/bench_geometry.h"

#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "host/app/provenance.h"
#include "host/geometry/grid_particles.h"
#include "host/geometry/mesh_check.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/shapes.h"
#include "host/geometry/tet_particles.h"
#include "host/geometry/voronoi_particles.h"
#include "host/scene/scene.h"

namespace pd {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadius = 0.1, kHeight = 0.3;  // the procedural shapes' size [m]

// Particles per spacing^3 of each kind, to turn a wanted count into a spacing: one cube per
// spacing^3; about 0.6 Poisson-disk sites per r^3 (measured on the sphere and spot.obj); about
// 1.25 tets per spacing^3 with the scenes' default TetGen bound of 2 spacing^3 (measured: 1.06
// on the sphere, 1.6 on spot.obj, whose coarse surface TetGen refines). The counts printed are
// the real ones.
double density(const std::string& particles) {
  if (particles == "grid") return 1;
  if (particles == "voronoi") return 0.6;
  return 1.25;
}

// The volume of the solid the particles will fill, before it is meshed at the final spacing.
double nominal_volume(const GeometryBenchOptions& o, const TriMesh* file_mesh) {
  if (o.shape != "mesh" && o.shape != "sphere" && o.shape != "vase")
    throw std::invalid_argument("bench-geometry: --shape must be sphere, vase or mesh, got '" + o.shape +
                                "'");
  if (o.particles == "shell") {  // the surface's area times the shell's depth
    const TriMesh surface = o.shape == "mesh"     ? *file_mesh
                            : o.shape == "sphere" ? sphere_mesh(kRadius, 0.002)
                                                  : vase_sheet(kRadius, kHeight, 0.002);
    return surface_area(surface) * o.shell_thickness;
  }
  if (o.shape == "mesh") return signed_volume(*file_mesh);
  if (o.shape == "sphere") return 4 * kPi / 3 * kRadius * kRadius * kRadius;
  return signed_volume(vase_mesh(kRadius, kHeight, o.shell_thickness, 0.002));
}

// Throws std::invalid_argument for a particle kind, shape or mesh the bench does not take.
void check_options(const GeometryBenchOptions& o) {
  const std::string& kind = o.particles;
  if (kind != "grid" && kind != "tets" && kind != "shell" && kind != "voronoi")
    throw std::invalid_argument("bench-geometry: --particles must be grid, tets, shell or voronoi, got '" +
                                kind + "'");
  // The vase's wall, or a shell's depth (one that folds the surface over is refused where the shell
  // is made).
  const bool wall = o.shape == "vase" && kind != "shell";
  if (wall && !(o.shell_thickness > 0 && o.shell_thickness < vase_foot(kRadius, kHeight)))
    throw std::invalid_argument("bench-geometry: --shell-thickness " + format_number(o.shell_thickness) +
                                " (the vase's wall) is out of range (allowed: in (0, " +
                                format_number(vase_foot(kRadius, kHeight)) + ") m, below the foot's radius)");
  if (kind == "shell" && !(o.shell_thickness > 0 && std::isfinite(o.shell_thickness)))
    throw std::invalid_argument("bench-geometry: --shell-thickness " + format_number(o.shell_thickness) +
                                " is out of range (allowed: a depth > 0 m)");
  if (o.shape == "mesh" && o.mesh.empty())
    throw std::invalid_argument("bench-geometry: --shape mesh needs --mesh FILE");
}

// The CSV file of --csv with its header when it is new, before the work: an unwritable path
// fails at once.
void start_csv(const std::string& path) {
  const bool fresh = !std::filesystem::exists(path);
  std::ofstream out(path, std::ios::app);
  if (fresh) out << "date,revision,cores,threads,shape,particles,count,spacing,volume_error,total_s,stages\n";
  if (!out) throw std::runtime_error("bench-geometry: cannot write " + path);
}

// Appends one row to the CSV file of --csv (start_csv wrote its header).
void append_csv_row(const GeometryBenchOptions& o, int threads, size_t particles, double spacing,
                    double error, double total, const std::vector<StageTime>& stages) {
  std::ofstream out(o.csv, std::ios::app);
  out << utc_now("%Y-%m-%dT%H:%M:%SZ") << ',' << git_revision() << ',' << std::thread::hardware_concurrency()
      << ',' << threads << ','
      << (o.shape == "mesh" ? std::filesystem::path(o.mesh).filename().string() : o.shape) << ','
      << o.particles << ',' << particles << ',' << spacing << ',' << error << ',' << total << ",\"";
  for (size_t k = 0; k < stages.size(); ++k)
    out << (k ? "; " : "") << stages[k].name << '=' << stages[k].seconds;
  out << "\"\n";
  if (!out) throw std::runtime_error("bench-geometry: cannot write " + o.csv);
}

}  // namespace

int bench_geometry_command(const GeometryBenchOptions& o) {
  check_options(o);
  if (!o.csv.empty()) start_csv(o.csv);
  const std::string& kind = o.particles;
  if (o.threads > 0) omp_set_num_threads(o.threads);
  const int threads = omp_get_max_threads();

  std::vector<StageTime> stages;
  const Clock::time_point t0 = Clock::now();
  Clock::time_point t = t0;
  TriMesh file_mesh;
  if (o.shape == "mesh") {
    file_mesh = read_mesh(o.mesh);
    check_solid(file_mesh, o.mesh, {});
    stages.push_back({"read + check mesh", seconds_since(t)});
  }
  const double volume = nominal_volume(o, &file_mesh);
  const double spacing = o.spacing > 0 ? o.spacing : std::cbrt(density(kind) * volume / double(o.count));

  // The solid, meshed as scene bodies are: curved surfaces with edges of the spacing (twice it
  // for tets).
  t = Clock::now();
  const double edge = kind == "tets" || kind == "shell" ? 2 * spacing : spacing;
  TriMesh solid;
  if (o.shape == "mesh") solid = file_mesh;
  if (o.shape == "sphere") solid = sphere_mesh(kRadius, edge);  // (a shell's surface for shells)
  if (o.shape == "vase")
    solid = kind == "shell" ? vase_sheet(kRadius, kHeight, edge)
                            : vase_mesh(kRadius, kHeight, o.shell_thickness, edge);
  if (o.shape != "mesh") stages.push_back({"surface mesh", seconds_since(t)});

  const int64_t budget = 100'000'000;
  const std::string name = o.shape == "mesh" ? o.mesh : o.shape;
  ParticleGeometry g;
  TetgenOptions tet;
  tet.quality = o.tet_quality;
  tet.keep_surface = o.tet_keep_surface;
  tet.max_volume = 2 * spacing * spacing * spacing;
  int layers = 0;
  double exact = 0;  // the volume the particles should add up to
  if (kind == "grid") g = grid_particles(solid, spacing, budget, name);
  if (kind == "voronoi") g = voronoi_particles(solid, spacing, o.seed, budget, name);
  if (kind == "tets") g = tet_particles(solid, tet, budget, name);
  if (kind == "shell") {
    layers = 1 + std::max(1, int(std::lround(o.shell_thickness / spacing)));
    g = shell_particles(solid, o.shell_thickness, layers, tet, budget, name);
    exact = signed_volume(fattened_shell(solid, o.shell_thickness, layers).solid);
  } else {
    exact = signed_volume(solid);
  }
  const double total = seconds_since(t0);
  if (g.size() == 0) {  // (a spacing past the shape: nothing to time, no volume to compare)
    char text[160];
    std::snprintf(text, sizeof text, "holds no particle at a spacing of %.4g m", spacing);
    throw std::invalid_argument("bench-geometry: the " + name + " " + text +
                                " (allowed: a smaller --spacing or a larger --count)");
  }
  stages.insert(stages.end(), g.stages.begin(), g.stages.end());
  const double error = (g.total_volume() - exact) / exact;

  std::printf("bench-geometry: %s %s, spacing %.6g m%s, %d threads, %u cores\n", kind.c_str(),
              o.shape == "mesh" ? o.mesh.c_str() : o.shape.c_str(), spacing,
              layers ? (", " + std::to_string(layers) + " layers").c_str() : "", threads,
              std::thread::hardware_concurrency());
  std::printf("particles %zu, volume %.9g m^3, relative volume error %.2e, %zu surface triangles\n", g.size(),
              g.total_volume(), error, solid.triangles.size());
  for (const StageTime& s : stages) std::printf("  %-40s %9.3f s\n", s.name.c_str(), s.seconds);
  std::printf("  %-40s %9.3f s\n", "total", total);

  if (!o.csv.empty()) append_csv_row(o, threads, g.size(), spacing, error, total, stages);
  return 0;
}

}  // namespace pd
