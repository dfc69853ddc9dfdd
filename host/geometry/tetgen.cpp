#include "host/geometry/tetgen.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <iterator>
#include <optional>
#include <sstream>
#include <thread>
#include <unordered_map>
#include <utility>

#include "host/geometry/inside_test.h"
#include "host/geometry/tet_cache.h"
#include "host/io/byte_file.h"
#include "host/io/interrupt.h"

extern char** environ;

namespace pd {

// What TetGen needs, for its failures' messages: a shell's inner surface is the mesh moved inward
// by shell_thickness, which crosses itself where the thickness passes the mesh's own.
const std::string kTetgenAllowed =
    "(allowed: a closed mesh without self-intersections; for particles = \"shell\", a shell_thickness "
    "below the mesh's own thickness and radii of curvature; particles = \"grid\" fills a mesh whose "
    "parts cross, as their union)";

namespace {

namespace fs = std::filesystem;

// A temporary folder removed on scope exit, or the caller's folder kept as it is.
class WorkDir {
 public:
  explicit WorkDir(const std::string& given) : keep_(!given.empty()) {
    if (keep_) {
      path_ = given;
      fs::create_directories(path_);
      return;
    }
    std::string pattern = (fs::temp_directory_path() / "perifrac-tetgen-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary folder for tetgen");
    path_ = pattern;
  }
  ~WorkDir() {
    std::error_code ec;
    if (!keep_) fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (fs::path(path_) / name).string(); }

 private:
  bool keep_;
  std::string path_;
};

// A point inside each cavity of a closed solid, for TetGen's hole list: without one TetGen fills
// the cavity (a shell of a closed surface would be a ball). A cavity is bounded by a connected
// component of the surface that faces inward (negative volume); its point lies a thousandth of a
// triangle's size off the component's largest triangle, on the side its normal points to (into the
// cavity), checked outside the solid; the next largest triangles are tried where it is not.
std::vector<Vec3d> cavity_points(const TriMesh& mesh) {
  const size_t n = mesh.triangles.size();
  std::vector<int32_t> part(n, -1);
  std::unordered_map<uint64_t, std::vector<int32_t>> by_edge;
  auto key = [](int32_t a, int32_t b) {
    return (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
  };
  for (size_t f = 0; f < n; ++f)
    for (int c = 0; c < 3; ++c)
      by_edge[key(mesh.triangles[f][c], mesh.triangles[f][(c + 1) % 3])].push_back(int32_t(f));
  int32_t parts = 0;
  for (size_t seed = 0; seed < n; ++seed) {
    if (part[seed] >= 0) continue;
    std::vector<int32_t> stack{int32_t(seed)};
    part[seed] = parts;
    while (!stack.empty()) {
      const Triangle& t = mesh.triangles[size_t(stack.back())];
      stack.pop_back();
      for (int c = 0; c < 3; ++c)
        for (int32_t g : by_edge[key(t[c], t[(c + 1) % 3])])
          if (part[size_t(g)] < 0) part[size_t(g)] = parts, stack.push_back(g);
    }
    ++parts;
  }
  // Each component's volume, and its triangles by area (largest first).
  std::vector<double> volume(size_t(parts), 0.0);
  std::vector<std::vector<std::pair<double, int32_t>>> by_area(static_cast<size_t>(parts));
  for (size_t f = 0; f < n; ++f) {
    const Triangle& t = mesh.triangles[f];
    const Vec3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    volume[size_t(part[f])] += dot(a, cross(b, c)) / 6;
    by_area[size_t(part[f])].push_back({norm(cross(b - a, c - a)), int32_t(f)});
  }
  std::vector<Vec3d> points;
  std::optional<InsideTest> inside;
  for (int32_t c = 0; c < parts; ++c) {
    if (!(volume[size_t(c)] < 0)) continue;
    std::vector<std::pair<double, int32_t>>& largest = by_area[size_t(c)];
    std::sort(largest.rbegin(), largest.rend());
    if (!inside) inside.emplace(mesh);
    for (size_t k = 0; k < std::min<size_t>(largest.size(), 16); ++k) {
      const Triangle& t = mesh.triangles[size_t(largest[k].second)];
      const Vec3d a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], d = mesh.vertices[t[2]];
      const Vec3d normal = cross(b - a, d - a);
      const double area2 = norm(normal);
      if (!(area2 > 0)) break;
      const Vec3d p = (1.0 / 3) * (a + b + d) + (1e-3 * std::sqrt(area2) / area2) * normal;
      if (!inside->inside(p)) {
        points.push_back(p);
        break;
      }
    }
  }
  return points;
}

void write_smesh(const TriMesh& mesh, const std::vector<Vec3d>& holes, const std::string& path) {
  std::ofstream out(path);
  char buf[128];
  out << mesh.vertices.size() << " 3 0 0\n";
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    std::snprintf(buf, sizeof buf, "%zu %.17g %.17g %.17g\n", v, mesh.vertices[v][0], mesh.vertices[v][1],
                  mesh.vertices[v][2]);
    out << buf;
  }
  out << mesh.triangles.size() << " 0\n";
  for (const Triangle& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  out << holes.size() << '\n';
  for (size_t h = 0; h < holes.size(); ++h) {
    std::snprintf(buf, sizeof buf, "%zu %.17g %.17g %.17g\n", h, holes[h][0], holes[h][1], holes[h][2]);
    out << buf;
  }
  out << "0\n";
  if (!out) throw std::runtime_error("cannot write " + path);
}

void write_nodes(const std::vector<Vec3d>& points, const std::string& path) {
  std::ofstream out(path);
  char buf[128];
  out << points.size() << " 3 0 0\n";
  for (size_t v = 0; v < points.size(); ++v) {
    std::snprintf(buf, sizeof buf, "%zu %.17g %.17g %.17g\n", v, points[v][0], points[v][1], points[v][2]);
    out << buf;
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

constexpr int kStopped = -2;      // run_program: the program ran past its time and was killed
constexpr int kSignalled = 1000;  // run_program: kSignalled + the signal that ended the program

// Runs argv with stdout and stderr to `log`; returns the exit status (-1 if it did not run,
// kStopped if it ran past `seconds` and was killed, kSignalled + the signal if one ended it). `while_running`
// (if set) is called once the program has started; when it throws, the program is killed and the exception
// goes on. An interrupted command (interrupt.h) kills the program and throws Interrupted.
int run_program(const std::vector<std::string>& argv, const std::string& log, double seconds,
                const std::function<void()>& while_running) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  if (while_running) {
    try {
      while_running();
    } catch (...) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      throw;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) return -1;
    if (InterruptGuard::signal_received()) {  // (the program is killed, then the command stops)
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      throw_if_interrupted("TetGen");
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      return kStopped;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  throw_if_interrupted("TetGen");  // (a terminal's Ctrl-C reaches the program too)
  return WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? kSignalled + WTERMSIG(status) : -1;
}

// How long TetGen may run: two minutes and 0.2 ms for each tet the volume bound allows (TetGen
// takes 10-20 us a tet: the vase at Levine's size, 577,199 tets, in 5-12 s), or the seconds in
// PERIFRAC_TETGEN_SECONDS. A solid whose surface crosses itself (a shell thicker than its mesh)
// can keep TetGen busy for ever.
double tetgen_seconds(const TriMesh& surface, const TetgenOptions& options) {
  if (const char* given = std::getenv("PERIFRAC_TETGEN_SECONDS"); given && *given) {
    char* end = nullptr;
    const double s = std::strtod(given, &end);
    if (*end != '\0' || !(s > 0) || !std::isfinite(s))
      throw std::invalid_argument(std::string("environment PERIFRAC_TETGEN_SECONDS='") + given +
                                  "': allowed is a number of seconds > 0 (unset: from the volume bound)");
    return s;
  }
  const double tets = options.max_volume > 0 ? std::fabs(signed_volume(surface)) / options.max_volume : 0;
  return 120 + 2e-4 * tets;
}

// The last non-empty lines of a log, joined on one line.
std::string log_tail(const std::string& log) {
  std::ifstream in(log);
  std::string line, last;
  std::vector<std::string> lines;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  for (size_t k = lines.size() > 3 ? lines.size() - 3 : 0; k < lines.size(); ++k)
    last += (last.empty() ? "" : " / ") + lines[k];
  return last.empty() ? "none" : "'" + last + "'";
}

// Reads "count ..." then `count` rows of an index and `width` numbers (the rest of each row,
// attributes and markers, skipped). The whole file is read at once and parsed by from_chars:
// TetGen's ASCII output of a 600k-tet mesh is about 30 MB.
template <class Row>
std::vector<Row> read_table(const std::string& path, int width, const std::string& name) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw MeshError(
        name, "tetgen wrote no " + fs::path(path).filename().string() + " (allowed: a tetgen that works)");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char* p = text.data();
  const char* const end = p + text.size();
  // Skips blanks, line ends and comments (# to the end of the line).
  auto skip_space = [&] {
    while (p < end) {
      if (*p == '#')
        while (p < end && *p != '\n') ++p;
      else if (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
        ++p;
      else
        break;
    }
  };
  auto skip_line = [&] {
    while (p < end && *p != '\n') ++p;
  };
  bool ok = true;
  auto number = [&](auto& value) {
    skip_space();
    const auto r = std::from_chars(p, end, value);
    if (r.ec != std::errc()) ok = false;
    p = r.ptr;
  };
  size_t count = 0;
  number(count);
  skip_line();
  std::vector<Row> rows(ok ? count : 0);
  for (size_t r = 0; r < rows.size() && ok; ++r) {
    long index = 0;
    number(index);
    for (int k = 0; k < width; ++k) number(rows[r][size_t(k)]);
    skip_line();  // attributes and markers
  }
  if (!ok)
    throw MeshError(name, "tetgen's " + fs::path(path).filename().string() +
                              " is truncated (allowed: a tetgen that works)");
  return rows;
}

}  // namespace

std::string find_tetgen() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/tetgen";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

TetMesh tetrahedralize(const TriMesh& surface, const TetgenOptions& options, const std::string& name) {
  const std::string program = find_tetgen();
  if (program.empty())
    throw MeshError(name,
                    "tetrahedral particles need the TetGen program, which is not on PATH "
                    "(allowed: install it, e.g. 'apt-get install tetgen', or use particles = \"grid\" "
                    "or \"voronoi\")");
  StageClock clock(options.stages);
  const WorkDir dir(options.work_dir);
  const std::vector<Vec3d> holes = cavity_points(surface);
  write_smesh(surface, holes, dir.file("in.smesh"));

  // Switches: PLC, [keep the surface,] quality, volume bound, inserted points, no mesh
  // optimization, 0-based, no .face or .edge file, quiet. The face neighbours are found here from
  // the tets (face_neighbors) rather than written by TetGen as .neigh and read back: on the vase
  // at Levine's size (577k tets) TetGen's output took 0.73 s with them and 0.31 s without
  // (bench/NOTES.md). TetGen 1.5's optimization (flips and
  // smoothing after the refinement, on by default) breaks the -a bound: on spot.obj with
  // a = 2e-5 it left 11 tets up to 1.42 a. Without it the bound holds and TetGen is ~10% faster.
  std::string switches = "-p";
  if (options.keep_surface) switches += "Y";
  char buf[64];
  if (options.quality > 0) {
    std::snprintf(buf, sizeof buf, "q%.6g", options.quality);
    switches += buf;
  }
  if (options.max_volume > 0) {
    std::snprintf(buf, sizeof buf, "a%.9g", options.max_volume);
    switches += buf;
  }
  if (!options.extra_points.empty()) {
    write_nodes(options.extra_points, dir.file("in.a.node"));
    switches += "i";
  }
  switches += "O0zFQ";
  clock.lap("tetgen input files");
  // The cache (tet_cache.h), unless the caller wants TetGen's own files in its folder.
  std::optional<TetCache> cache;
  if (const std::string folder = tet_cache_folder(); !folder.empty() && options.work_dir.empty()) {
    std::string input = switches + '\n' + read_file_bytes(dir.file("in.smesh"));
    if (!options.extra_points.empty()) input += '\n' + read_file_bytes(dir.file("in.a.node"));
    cache.emplace(folder, input);
    if (std::optional<TetMesh> kept = cache->load()) {
      clock.lap("tets from the cache");
      if (options.while_running) options.while_running();
      return std::move(*kept);
    }
  }
  const double seconds = tetgen_seconds(surface, options);
  int status = run_program({program, switches, dir.file("in.smesh")}, dir.file("tetgen.log"), seconds,
                           options.while_running);
  // TetGen 1.5.0 can crash carving a hole where it also inserts points (a cube's shell): then it
  // meshes the cavities too, and their tets are dropped below.
  const bool mesh_cavities = status != 0 && status != kStopped && !holes.empty();
  if (mesh_cavities) {
    write_smesh(surface, {}, dir.file("in.smesh"));
    status = run_program({program, switches, dir.file("in.smesh")}, dir.file("tetgen.log"), seconds,
                         options.while_running);
  }
  clock.lap("tetgen " + switches);
  if (status == kStopped)
    throw MeshError(name, "tetgen " + switches + " was stopped after " + std::to_string(int(seconds)) +
                              " s without a result " + kTetgenAllowed);
  if (status != 0)
    throw MeshError(
        name, "tetgen " + switches +
                  (status >= kSignalled ? " crashed (signal " + std::to_string(status - kSignalled) + ")"
                                        : " failed (exit status " + std::to_string(status) + ")") +
                  ", its last words: " + log_tail(dir.file("tetgen.log")) + " " + kTetgenAllowed);

  // The vertices read on a thread of their own beside the tets.
  TetMesh mesh;
  auto vertices =
      std::async(std::launch::async, [&] { return read_table<Vec3d>(dir.file("in.1.node"), 3, name); });
  mesh.tets = read_table<std::array<int32_t, 4>>(dir.file("in.1.ele"), 4, name);
  mesh.vertices = vertices.get();
  if (mesh.tets.empty())
    throw MeshError(name, "tetgen produced no tetrahedra (allowed: a solid of non-zero volume)");
  for (const auto& tet : mesh.tets)
    for (int32_t v : tet)
      if (v < 0 || size_t(v) >= mesh.vertices.size())
        throw MeshError(name, "tetgen's in.1.ele names vertex " + std::to_string(v) + " of " +
                                  std::to_string(mesh.vertices.size()) + " (allowed: a tetgen that works)");
  if (mesh_cavities) {  // the tets of the cavities, bounded by the surface, have their centroid outside it
    const InsideTest inside(surface);
    const auto cavity = [&](const std::array<int32_t, 4>& t) {
      return !inside.inside(
          0.25 * (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]] + mesh.vertices[t[3]]));
    };
    mesh.tets.erase(std::remove_if(mesh.tets.begin(), mesh.tets.end(), cavity), mesh.tets.end());
  }
  // Positive orientation, then the neighbour opposite each corner.
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    if (mesh.volume(t) < 0) std::swap(mesh.tets[t][0], mesh.tets[t][1]);
  mesh.neighbors = face_neighbors(mesh.tets, mesh.vertices.size());
  if (cache) cache->store(mesh);  // (before the lap, where an interrupt would stop the set-up)
  clock.lap("tetgen output files");
  return mesh;
}

}  // namespace pd
