#include "host/app/bench_fragments.h"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "cuda/engine/material.h"
#include "host/app/provenance.h"
#include "host/fragments/adjacency.h"
#include "host/fragments/fragment_output.h"
#include "host/fragments/fragments_file.h"
#include "host/fragments/piece_mesh.h"
#include "host/fragments/ply_points.h"
#include "host/geometry/shapes.h"
#include "host/geometry/voronoi_particles.h"

namespace pd {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr double kPi = 3.14159265358979323846;
constexpr double kSide = 1e-3;   // cube side of the grid and tet blocks [m]
constexpr double kRadius = 0.1;  // the Voronoi sphere [m]

// One body of glass-like particles with its elements' geometry.
struct Body {
  SimulationInput in;
  EmbeddedTets tets;
  ParticleGeometry cells;  // voronoi only
  std::string shape;       // for the report
  std::vector<StageTime> setup;
};

Material glass(double lambda, double horizon) {
  Material m;
  m.horizon = real(horizon * lambda);
  m.spacing = real(lambda);
  m.contact_spacing = real(lambda);
  m.micromodulus = real(pmb_micromodulus(32.81e9, horizon * lambda));
  m.compression_alpha = real(0.25);
  return m;
}

void add(Body& b, const Vec3d& x, double volume) {
  b.in.particles.add({real(x[0]), real(x[1]), real(x[2])}, {0, 0, 0}, real(volume), real(2440 * volume),
                     real(1e-3), 0, 0);
}

// A cube of n^3 grid cubes.
Body grid_body(int64_t count, double horizon) {
  Body b;
  const int64_t n = std::max<int64_t>(2, std::llround(std::cbrt(double(count))));
  b.shape = std::to_string(n) + "^3 cubes of 1 mm";
  b.in.materials.count = 1;
  b.in.materials.m[0] = glass(kSide, horizon);
  for (int64_t k = 0; k < n; ++k)
    for (int64_t j = 0; j < n; ++j)
      for (int64_t i = 0; i < n; ++i)
        add(b, {double(i) * kSide, double(j) * kSide, double(k) * kSide}, kSide * kSide * kSide);
  return b;
}

// A cube of m^3 cubes of 1 mm, each cut into the 6 tets around its diagonal (Kuhn).
Body tet_body(int64_t count, double horizon) {
  Body b;
  const int m = int(std::max<int64_t>(2, std::llround(std::cbrt(double(count) / 6))));
  b.shape = std::to_string(m) + "^3 cubes of 6 tets, 1 mm";
  b.in.materials.count = 1;
  b.in.materials.m[0] = glass(kSide, horizon);
  auto id = [&](int i, int j, int k) { return int32_t(i + (m + 1) * (j + (m + 1) * k)); };
  for (int k = 0; k <= m; ++k)
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i) b.tets.vertices.push_back({i * kSide, j * kSide, k * kSide});
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        for (const auto& a : axes) {
          int c[3] = {i, j, k};
          std::array<int32_t, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          Vec3d centre = b.tets.vertices[size_t(t[0])];
          for (int s = 0; s < 3; ++s) {
            ++c[a[s]];
            t[size_t(s) + 1] = id(c[0], c[1], c[2]);
            centre = centre + b.tets.vertices[size_t(t[size_t(s) + 1])];
          }
          b.tets.particle.push_back(int32_t(b.tets.tets.size()));
          b.tets.tets.push_back(t);
          add(b, 0.25 * centre, kSide * kSide * kSide / 6);
        }
  return b;
}

// Voronoi cells of Poisson-disk sites in a sphere (about 0.6 sites per r^3).
Body voronoi_body(int64_t count, double horizon) {
  Body b;
  const double r = std::cbrt(0.6 * 4 * kPi / 3 * kRadius * kRadius * kRadius / double(count));
  b.shape = "a sphere of radius 0.1 m, r = " + std::to_string(r * 1e3).substr(0, 5) + " mm";
  const Clock::time_point t0 = Clock::now();
  b.cells = voronoi_particles(sphere_mesh(kRadius, r), r, 1, 100'000'000, "sphere");
  b.setup.push_back({"Voronoi cells (geometry stage)", seconds_since(t0)});
  std::vector<double> nearest = b.cells.lambda;
  std::nth_element(nearest.begin(), nearest.begin() + long(nearest.size() / 2), nearest.end());
  b.in.materials.count = 1;
  b.in.materials.m[0] = glass(nearest[nearest.size() / 2], horizon);
  for (size_t i = 0; i < b.cells.size(); ++i) add(b, b.cells.position[i], b.cells.volume[i]);
  return b;
}

// Pairs of elements across faces.
ElementAdjacency face_adjacency(const ElementComplex& c) {
  std::vector<std::pair<int32_t, int32_t>> pairs;
  for (size_t e = 0; e < c.size(); ++e)
    for (int64_t f = c.face_start[e]; f < c.face_start[e + 1]; ++f)
      if (c.face_other[size_t(f)] > int32_t(e)) pairs.emplace_back(int32_t(e), c.face_other[size_t(f)]);
  return adjacency_from_pairs(c.size(), std::move(pairs));
}

// Breaks (in both families) every bond whose ends `apart` says are apart.
template <class Apart>
void break_bonds(BondLists& bonds, Apart apart) {
  const BondsView v = bonds.view();
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < v.n; ++i)
    for (int32_t k = 0; k < v.count[i]; ++k) {
      int32_t& nb = bonds.neighbor[size_t(v.slot(i, k))];
      if (bond_intact(nb) && apart(i, nb)) nb = ~nb;
    }
}

// The per-frame stages, in the order FragmentOutput::process runs them.
const char* const kStages[] = {"components",          "fits",           "crack mesh update",
                               "blending (4 frames)", "fragments file", "points PLY",
                               "crack surface",       "crack OBJ",      "crack PLY"};
constexpr int kStageCount = 9;
const char* const kStates[] = {"intact", "cut", "shattered"};

// What the three states took: per stage the first frame after the change and the mean of the
// next ones [s], the rest-space pieces' build and write, and the sizes.
struct StateTimes {
  double first[3][kStageCount] = {}, then[3][kStageCount] = {}, build[3] = {}, write[3] = {};
  size_t fragments[3] = {}, triangles[3] = {};
  double megabytes[3] = {};
};

// The frame loop's working data: the frame, its components, fits and crack surface, and the
// split blending.
struct FrameWork {
  FrameData frame;
  Components components;
  std::vector<Fragment> fits;
  CrackSurface surface;
  FragmentSmoother smoother{4};
};

// One timed frame `global_frame`, the body turned by 1e-3 rad per frame about `centre`: each stage
// of FragmentOutput::process, its time over `frames` (the frames it is averaged over) added to
// into[stage]. Only this frame's files are kept in `dir`: a shattered body writes hundreds of MB
// per frame.
void time_frame(const ParticleSet& ps, const BondLists& bonds, ComponentFinder& finder, EmbeddedMesh& mesh,
                const Vec3d& centre, int64_t global_frame, const std::string& dir, FrameWork& w, double* into,
                int frames) {
  const double angle = 1e-3 * double(global_frame), c = std::cos(angle), s = std::sin(angle);
  FrameData& frame = w.frame;
  frame.frame = global_frame;
  frame.position.resize(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    const double x = ps.rest[i].x - centre[0], y = ps.rest[i].y - centre[1];
    frame.position[i] = {real(centre[0] + c * x - s * y), real(centre[1] + s * x + c * y), ps.rest[i].z};
  }
  Clock::time_point t = Clock::now();
  auto lap = [&](int stage) {
    const Clock::time_point now = Clock::now();
    into[stage] += std::chrono::duration<double>(now - t).count() / frames;
    t = now;
  };
  finder.find(bonds, w.components);
  frame.component = w.components.id;
  lap(0);
  align_fragments(w.components, ps.rest, frame.position, ps.mass, w.fits);
  lap(1);
  mesh.update(bonds, frame.position, w.components, w.fits);
  lap(2);
  w.smoother.apply(w.components, ps.rest, frame.position, ps.mass, w.fits);
  lap(3);
  write_fragments_file(dir + "/" + fragments_file_name(global_frame), global_frame, 0, 0, w.fits);
  lap(4);
  write_ply_points(dir + "/" + points_file_name(global_frame), frame);
  lap(5);
  mesh.surface(w.surface);
  lap(6);
  write_crack_obj(dir + "/" + crack_mesh_file_name(global_frame, "obj"), w.surface, "bench");
  lap(7);
  write_crack_ply(dir + "/" + crack_mesh_file_name(global_frame, "ply"), w.surface, "bench");
  lap(8);
  if (global_frame > 0)
    for (const std::string& old :
         {fragments_file_name(global_frame - 1), points_file_name(global_frame - 1),
          crack_mesh_file_name(global_frame - 1, "obj"), crack_mesh_file_name(global_frame - 1, "ply")})
      std::filesystem::remove(dir + "/" + old);
}

// Times the per-frame stages in the three states: intact, cut into blocks^3 blocks, every bond
// broken (the bonds are broken on the way); then, per state, the rest-space pieces (written once
// per run by `perifrac run`).
StateTimes time_states(const FragmentsBenchOptions& o, const ParticleSet& ps, BondLists& bonds,
                       ComponentFinder& finder, EmbeddedMesh& mesh, const std::string& dir) {
  Box3d box;
  for (const Vec3& p : ps.rest) box.add({p.x, p.y, p.z});
  auto block = [&](int32_t i) {
    const Vec3& p = ps.rest[size_t(i)];
    int cell[3];
    const double x[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a)
      cell[a] = std::min(o.blocks - 1, int(double(o.blocks) * (x[a] - box.lo[a]) / (box.hi[a] - box.lo[a])));
    return cell[0] + o.blocks * (cell[1] + o.blocks * cell[2]);
  };
  const Vec3d centre = box.center();
  FrameWork w;
  w.frame.velocity.assign(ps.size(), {0, 0, 0});
  w.frame.damage.assign(ps.size(), 0);
  w.frame.body.assign(ps.size(), 0);
  StateTimes r;
  int64_t global_frame = 0;
  for (int state = 0; state < 3; ++state) {
    if (state == 1) break_bonds(bonds, [&](int32_t i, int32_t j) { return block(i) != block(j); });
    if (state == 2) break_bonds(bonds, [](int32_t, int32_t) { return true; });
    for (int f = 0; f < o.frames; ++f, ++global_frame)
      time_frame(ps, bonds, finder, mesh, centre, global_frame, dir, w,
                 f == 0 ? r.first[state] : r.then[state], f == 0 ? 1 : o.frames - 1);
    Clock::time_point t = Clock::now();
    const FragmentMesh pieces = fragment_pieces(mesh.elements(), w.components);
    r.build[state] = seconds_since(t);
    t = Clock::now();
    const std::string obj = dir + "/fragments.obj";
    write_obj(obj, pieces);
    r.write[state] = seconds_since(t);
    r.fragments[state] = w.components.count();
    r.triangles[state] = w.surface.triangles.size();
    r.megabytes[state] = double(std::filesystem::file_size(obj)) / 1e6;
  }
  return r;
}

// The table: one row per stage, one column per state.
void print_state_table(const StateTimes& r, int frames) {
  std::printf("per frame [ms], the first frame after the change / the mean of the next %d:\n", frames - 1);
  std::printf("  %-22s", "");
  for (int state = 0; state < 3; ++state) std::printf(" %21s", kStates[state]);
  std::printf("\n  %-22s", "fragments");
  for (int state = 0; state < 3; ++state) std::printf(" %21zu", r.fragments[state]);
  for (int k = 0; k < kStageCount; ++k) {
    std::printf("\n  %-22s", kStages[k]);
    for (int state = 0; state < 3; ++state)
      std::printf(" %10.1f / %8.1f", 1e3 * r.first[state][k], 1e3 * r.then[state][k]);
  }
  std::printf("\n  %-22s", "crack triangles");
  for (int state = 0; state < 3; ++state) std::printf(" %21zu", r.triangles[state]);
  std::printf("\nonce per run [ms]:\n  %-22s", "pieces (build)");
  for (int state = 0; state < 3; ++state) std::printf(" %21.1f", 1e3 * r.build[state]);
  std::printf("\n  %-22s", "pieces OBJ (write)");
  for (int state = 0; state < 3; ++state)
    std::printf(" %10.1f %7.1f MB", 1e3 * r.write[state], r.megabytes[state]);
  std::printf("\n");
  std::fflush(stdout);
}

// Appends the table and the set-up stages to the CSV file `path` (a header first when it is new).
void append_csv_rows(const std::string& path, const std::string& kind, size_t n, int threads,
                     const StateTimes& r, const std::vector<StageTime>& setup) {
  const bool fresh = !std::filesystem::exists(path);
  std::ofstream csv(path, std::ios::app);
  if (fresh) csv << "date,revision,cores,threads,particles,count,state,fragments,stage,first_ms,then_ms\n";
  const std::string stamp = utc_now("%Y-%m-%dT%H:%M:%SZ") + "," + git_revision() + "," +
                            std::to_string(std::thread::hardware_concurrency()) + "," +
                            std::to_string(threads) + "," + kind + "," + std::to_string(n) + ",";
  for (int state = 0; state < 3; ++state) {
    const std::string row = stamp + kStates[state] + "," + std::to_string(r.fragments[state]) + ",";
    for (int k = 0; k < kStageCount; ++k)
      csv << row << kStages[k] << ',' << 1e3 * r.first[state][k] << ',' << 1e3 * r.then[state][k] << '\n';
    csv << row << "pieces (build)," << 1e3 * r.build[state] << ",\n"
        << row << "pieces OBJ," << 1e3 * r.write[state] << ",\n";
  }
  for (const StageTime& s : setup) csv << stamp << "set-up,1," << s.name << ',' << 1e3 * s.seconds << ",\n";
  if (!csv) throw std::runtime_error("bench-fragments: cannot write " + path);
}

}  // namespace

int bench_fragments_command(const FragmentsBenchOptions& o) {
  const std::string& kind = o.particles;
  if (kind != "grid" && kind != "tets" && kind != "voronoi")
    throw std::invalid_argument("bench-fragments: --particles must be grid, tets or voronoi, got '" + kind +
                                "'");
  if (o.count < 8 || o.frames < 2 || o.blocks < 2 || o.horizon < 0)
    throw std::invalid_argument(
        "bench-fragments: need --count >= 8, --frames >= 2, --blocks >= 2, --horizon >= 0");
  if (o.threads > 0) omp_set_num_threads(o.threads);
  const int threads = omp_get_max_threads();
  const double horizon = o.horizon > 0 ? o.horizon : kind == "tets" ? 1.5 : 3.0;
  const bool temporary = o.out.empty();
  const std::string dir = temporary ? (std::filesystem::temp_directory_path() /
                                       ("perifrac-bench-fragments-" + std::to_string(getpid())))
                                          .string()
                                    : o.out;
  std::filesystem::create_directories(dir);

  // The body, its families and the one-off set-up of the fragment outputs.
  Body b = kind == "grid"   ? grid_body(o.count, horizon)
           : kind == "tets" ? tet_body(o.count, horizon)
                            : voronoi_body(o.count, horizon);
  const ParticleSet& ps = b.in.particles;
  const size_t n = ps.size();
  Clock::time_point t = Clock::now();
  BondLists bonds;
  make_cpu_engine(b.in)->read_bonds(bonds);
  b.setup.push_back({"families (engine set-up + copy)", seconds_since(t)});
  int64_t stored = 0;
  for (int32_t c : bonds.count) stored += c;
  const std::vector<real> spacing = particle_spacing(ps, b.in.materials);
  t = Clock::now();
  ElementAdjacency adjacency = kind == "grid"   ? grid_adjacency(bonds, ps.rest, spacing)
                               : kind == "tets" ? face_adjacency(tet_complex(b.tets))
                                                : b.cells.adjacency;
  b.setup.push_back({kind == "grid"   ? "adjacency (grid_adjacency)"
                     : kind == "tets" ? "adjacency (tet faces)"
                                      : "adjacency (copy)",
                     seconds_since(t)});
  t = Clock::now();
  ComponentFinder finder(adjacency, bonds);
  b.setup.push_back({"component finder set-up", seconds_since(t)});
  t = Clock::now();
  std::vector<VoronoiElements> voronoi;
  if (kind == "voronoi") voronoi.push_back({0, &b.cells});
  VoronoiComplexReport report;
  ElementComplex elements = particle_elements(ps.rest, spacing, adjacency, b.tets, voronoi, &report);
  b.setup.push_back({"element complex", seconds_since(t)});
  const size_t vertices = elements.vertices.size(), faces = elements.faces();
  t = Clock::now();
  EmbeddedMesh mesh(std::move(elements), adjacency, bonds, ps.rest, ps.mass);
  b.setup.push_back({"crack mesh set-up", seconds_since(t)});

  std::printf(
      "bench-fragments: %s, %zu particles (%s), delta = %g lambda, %lld stored bonds, %d threads, %u cores\n",
      kind.c_str(), n, b.shape.c_str(), horizon, (long long)stored, threads,
      std::thread::hardware_concurrency());
  std::printf("elements: %zu vertices, %zu faces, %zu adjacent pairs", vertices, faces, finder.pairs());
  if (kind == "voronoi")
    std::printf("; %zu cells cut by the surface, %zu faces whose loops did not close", report.boundary_cells,
                report.failed_faces);
  std::printf("\n");
  for (const StageTime& s : b.setup) std::printf("  %-40s %9.3f s\n", s.name.c_str(), s.seconds);

  const StateTimes times = time_states(o, ps, bonds, finder, mesh, dir);
  print_state_table(times, o.frames);
  if (!o.csv.empty()) append_csv_rows(o.csv, kind, n, threads, times, b.setup);
  if (temporary) std::filesystem::remove_all(dir);
  return 0;
}

}  // namespace pd
