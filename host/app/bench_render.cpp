#include "host/app/bench_render.h"

#include <omp.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "host/app/backend_choice.h"
#include "host/app/bench_two_level.h"
#include "host/app/provenance.h"
#include "host/app/run.h"
#include "host/io/atomic_file.h"
#include "host/io/json_text.h"
#include "render/renderer.h"
#include "render/tet_lattice.h"
#include "render/traverse.h"
#if defined(PERIFRAC_HAS_EMBREE)
#include "render/embree_scene.h"
#endif

namespace pd {

namespace {

// The synthetic scene: a slab nx x ny x nz lattice cells of side 1 / nx, its bottom at y = 0,
// centred in x and z.
struct BenchScene {
  PrimitiveSet prims;
  int64_t nx = 0, ny = 0, nz = 0;
  std::string description;
};

BenchScene make_bench_scene(const RenderBenchOptions& o) {
  BenchScene b;
  const bool tets = o.scene == "slab";
  const double cells = double(o.count) / (tets ? 6 : 1);
  b.ny = std::max<int64_t>(1, std::lround(std::cbrt(cells) / 4.64));  // about a tenth of the width
  b.nx = b.nz = std::max<int64_t>(1, std::lround(std::sqrt(cells / double(b.ny))));
  const double h = 1.0 / double(b.nx);
  auto corner = [&](int64_t i, int64_t j, int64_t k) {
    return Vec3{real((double(i) - 0.5 * double(b.nx)) * h), real(double(j) * h),
                real((double(k) - 0.5 * double(b.nz)) * h)};
  };
  if (tets) {
    add_tet_lattice(&b.prims, b.nx, b.ny, b.nz, h, 0.2);
    b.description = std::to_string(b.prims.size()) + " tetrahedra (" + std::to_string(b.nx) + " x " +
                    std::to_string(b.ny) + " x " + std::to_string(b.nz) + " jittered cells, 6 each)";
    return b;
  }
  // Cubes, axis-aligned or the whole lattice turned by 30 degrees about (1, 2, 3).
  Vec3 axis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (o.scene == "turned-cubes") {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(3.14159265358979323846 / 6, Eigen::Vector3d(1, 2, 3).normalized())
            .toRotationMatrix();
    for (int col = 0; col < 3; ++col) axis[col] = {real(r(0, col)), real(r(1, col)), real(r(2, col))};
  }
  for (int64_t k = 0; k < b.nz; ++k)
    for (int64_t j = 0; j < b.ny; ++j)
      for (int64_t i = 0; i < b.nx; ++i) {
        const Vec3 c = corner(i, j, k) + Vec3{real(h / 2), real(h / 2), real(h / 2)};
        if (o.scene == "cubes")
          b.prims.add_cube(c, real(h / 2));
        else
          b.prims.add_oriented_cube(c.x * axis[0] + c.y * axis[1] + c.z * axis[2], real(h / 2), axis);
      }
  b.description = std::to_string(b.prims.size()) + " " + (o.scene == "cubes" ? "cubes" : "turned cubes") +
                  " (" + std::to_string(b.nx) + " x " + std::to_string(b.ny) + " x " + std::to_string(b.nz) +
                  ")";
  return b;
}

// The primary rays of the view traced without shading on the host (the renderer's short-stack
// traversal, OpenMP over rows): the nearest t of sample 0 per pixel (INFINITY: miss) and the
// wall time.
struct HostTrace {
  std::vector<float> depth;
  double seconds = 0;
  double hit_fraction = 0;                      // of the pixels' first samples
  double nodes_per_ray = 0, tests_per_ray = 0;  // from a second, counting pass
};

HostTrace trace_on_host(const RenderScene& scene, const CameraFrame& camera, int spp) {
  HostTrace out;
  out.depth.assign(size_t(camera.width) * size_t(camera.height), INFINITY);
  const KdTreeView tree = scene.tree.view();
  const PrimitivesView prims = scene.prims.view();
  const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 4)
  for (int32_t y = 0; y < camera.height; ++y)
    for (int32_t x = 0; x < camera.width; ++x)
      for (int k = 0; k < spp; ++k) {
        real u, v;
        pixel_sample(k, spp, &u, &v);
        const Hit h =
            traverse_short_stack<kRenderStackSize>(tree, prims, camera_ray(camera, real(x) + u, real(y) + v));
        if (k == 0 && h.prim >= 0) out.depth[size_t(y) * size_t(camera.width) + size_t(x)] = float(h.t);
      }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The work per ray: kd-tree nodes visited and primitive tests (sample 0 of each pixel).
  int64_t nodes = 0, tests = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : nodes, tests)
  for (int32_t y = 0; y < camera.height; ++y)
    for (int32_t x = 0; x < camera.width; ++x) {
      real u, v;
      pixel_sample(0, spp, &u, &v);
      TraversalStats st;
      traverse_short_stack<kRenderStackSize>(tree, prims, camera_ray(camera, real(x) + u, real(y) + v), &st);
      nodes += st.nodes;
      tests += st.tests;
    }
  const double pixels = double(camera.width) * double(camera.height);
  out.hit_fraction =
      double(std::count_if(out.depth.begin(), out.depth.end(), [](float t) { return !std::isinf(t); })) /
      pixels;
  out.nodes_per_ray = double(nodes) / pixels;
  out.tests_per_ray = double(tests) / pixels;
  return out;
}

// The scene to render: the bench scene's primitives with albedos and materials, its kd-tree built
// serially, then in parallel (the same tree); both builds and the whole scene's set-up timed.
struct TimedScene {
  RenderScene scene;
  double serial_build = 0;   // the serial kd-tree build [s]
  double scene_seconds = 0;  // the scene with the hidden-element search and the parallel build [s]
};

// Makes the render scene of `b` (its primitives moved in) and reports what the kd-tree left out and
// what its builds took.
TimedScene make_timed_scene(BenchScene& b, const RenderBenchOptions& o, const KdBuildOptions& build) {
  KdBuildOptions serial_options = build;
  serial_options.threads = 1;
  std::vector<Vec3> albedo(size_t(b.prims.size()));
  for (size_t i = 0; i < albedo.size(); ++i)
    albedo[i] = {real(0.55 + 0.1 * double(i % 3)), real(0.6), real(0.65)};
  std::vector<uint8_t> material(o.material == "glass" ? albedo.size() : 0, kMaterialGlass);
  const HiddenElements hidden = o.keep_hidden ? HiddenElements::kKeep : HiddenElements::kCull;
  TimedScene r;
  r.serial_build =
      make_render_scene(b.prims, albedo, material, serial_options, hidden).tree.stats.build_seconds;
  const auto scene_start = std::chrono::steady_clock::now();
  r.scene = make_render_scene(std::move(b.prims), std::move(albedo), std::move(material), build, hidden);
  r.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - scene_start).count();
  const RenderScene& scene = r.scene;
  const KdTreeStats& t = scene.tree.stats;
  const int64_t in_tree = scene.prims.size() - scene.hidden;
  std::printf("hidden      %lld of %d primitives left out of the kd-tree (%s)\n", (long long)scene.hidden,
              scene.prims.size(), o.keep_hidden ? "--keep-hidden: none looked for" : "hidden_tets.h");
  std::printf(
      "kd-tree     build %.3f s serial, %.3f s on %d threads (scene with the hidden-element search %.3f s); "
      "%.2f M nodes, depth %d, %.2f references per primitive in the tree\n",
      r.serial_build, t.build_seconds, t.threads, r.scene_seconds, 1e-6 * double(t.nodes), t.depth,
      double(t.prim_refs) / double(std::max<int64_t>(1, in_tree)));
  return r;
}

// The bench's view: looking down at 50 degrees onto the slab's centre from a distance at which the
// slab fills the 16:9 frame, so that nearly every primary ray meets the primitives.
Camera bench_camera(const RenderScene& scene) {
  Camera camera;
  const Box& bb = scene.tree.bounds;
  const real extent = rmax(bb.hi.x - bb.lo.x, bb.hi.z - bb.lo.z);
  camera.look_at = real(0.5) * (bb.lo + bb.hi);
  camera.eye = camera.look_at + extent * Vec3{0, real(0.85), real(0.72)};
  camera.vfov_degrees = 35;
  return camera;
}

// What the renders on the backend took: the warm-up (whose ray counts are reported), the best and
// the sum of the timed ones.
struct RenderTimes {
  RenderResult first;
  double best = INFINITY, total = 0;
};

// Renders the bench view on the backend: one warm-up, then `repeat` timed renders.
RenderTimes time_renders(Renderer& renderer, const RenderScene& scene, const Camera& camera,
                         const RenderBenchOptions& o) {
  RenderSettings s;
  s.width = o.width;
  s.height = o.height;
  s.spp = o.spp;
  s.count_rays = true;
  s.floor_y = scene.tree.bounds.lo.y;
  s.plank_width = real(0.2);
  s.fade_distance = real(20);
  RenderTimes r;
  r.first = renderer.render_frame(scene, camera, s);
  for (int k = 0; k < o.repeat; ++k) {
    const RenderResult t = renderer.render_frame(scene, camera, s);
    r.best = std::min(r.best, t.seconds);
    r.total += t.seconds;
  }
  return r;
}

// Embree on the same primitives, triangulated, against the renderer and the host traversal (when
// built in and not turned off): reported, and returned as the results file's "embree" entry.
std::string embree_baseline(const RenderBenchOptions& o, [[maybe_unused]] const RenderScene& scene,
                            [[maybe_unused]] const CameraFrame& frame, [[maybe_unused]] const HostTrace& host,
                            [[maybe_unused]] const RenderTimes& render, [[maybe_unused]] int threads) {
  std::ostringstream json;
#if defined(PERIFRAC_HAS_EMBREE)
  if (o.embree) {
    const double primary_rate = double(render.first.rays) / render.best;
    const double host_rate = double(render.first.rays) / host.seconds;
    const EmbreeScene embree(scene.prims);
    const EmbreeScene::PrimaryTrace e = embree.trace_primary(frame, o.spp);
    const double rate = double(render.first.rays) / e.seconds, agree = depth_agreement(host.depth, e.depth);
    std::printf(
        "embree      %s high-quality BVH of %zu triangles %.3f s; rtcIntersect1 primary rays, %d "
        "threads: %.3f s, %.3e rays/s\n",
        EmbreeScene::version().c_str(), embree.triangles(), embree.build_seconds(), threads, e.seconds, rate);
    std::printf(
        "compare     renderer primary rays/s over Embree's: %.2f; host traversal over Embree's: %.2f; depth "
        "agrees on %.4f%% of pixels\n",
        primary_rate / rate, host_rate / rate, 100 * agree);
    json << ",\n  \"embree\": {\"version\": \"" << EmbreeScene::version()
         << "\", \"triangles\": " << embree.triangles() << ", \"build_seconds\": " << embree.build_seconds()
         << ", \"threads\": " << threads << ", \"seconds\": " << e.seconds
         << ", \"primary_rays_per_s\": " << rate << ", \"depth_agreement\": " << agree << "}";
  }
#else
  if (o.embree) std::printf("embree      not built in (install libembree-dev and configure again)\n");
#endif
  return json.str();
}

// The per-frame rebuild against two levels (bench_two_level.h), with --fragments: reported, and
// returned as the results file's "two_level" entry.
std::string two_level_comparison(const RenderBenchOptions& o, const BenchScene& b, const RenderScene& scene,
                                 const CameraFrame& frame, const KdBuildOptions& build,
                                 int64_t primary_rays) {
  std::ostringstream json;
  if (o.fragments <= 0) return json.str();
  const TwoLevelReport t2 =
      measure_two_level(scene.prims, b.nx, b.ny, b.nz, o.scene == "slab" ? 6 : 1, o.fragments, frame, build);
  std::printf(
      "two-level   %d fragments moved apart: rest trees %.3f s (once per fragment); per frame top-level "
      "tree "
      "%.4f s against one rebuilt tree %.3f s\n",
      t2.fragments, t2.rest_build_seconds, t2.top_build_seconds, t2.world_build_seconds);
  std::printf(
      "two-level   host trace of the primary rays: one tree %.3e rays/s, two levels %.3e rays/s (%.2f "
      "fragment "
      "trees entered per ray); %.4f%% of pixels agree\n",
      double(primary_rays / o.spp) / t2.world_trace_seconds,
      double(primary_rays / o.spp) / t2.two_level_trace_seconds, t2.instances_per_ray, 100 * t2.agreement);
  json << ",\n  \"two_level\": {\"fragments\": " << t2.fragments
       << ", \"rest_build_seconds\": " << t2.rest_build_seconds
       << ", \"top_build_seconds\": " << t2.top_build_seconds
       << ", \"world_build_seconds\": " << t2.world_build_seconds
       << ", \"world_trace_seconds\": " << t2.world_trace_seconds
       << ", \"two_level_trace_seconds\": " << t2.two_level_trace_seconds
       << ", \"instances_per_ray\": " << t2.instances_per_ray << ", \"agreement\": " << t2.agreement << "}";
  return json.str();
}

// Throws std::invalid_argument naming an option out of its range.
void check_options(const RenderBenchOptions& o) {
  if (o.scene != "slab" && o.scene != "cubes" && o.scene != "turned-cubes")
    throw std::invalid_argument("bench-render: --scene '" + o.scene +
                                "' (allowed: slab, cubes, turned-cubes)");
  if (o.material != "opaque" && o.material != "glass")
    throw std::invalid_argument("bench-render: --material '" + o.material + "' (allowed: opaque, glass)");
  if (o.count < 1 || o.width < 16 || o.height < 16 || o.spp < 1 || o.repeat < 1)
    throw std::invalid_argument(
        "bench-render: need --count >= 1, --width/--height >= 16, --spp >= 1, --repeat >= 1");
}

// The kd-tree build knobs of the options (negative: the default).
KdBuildOptions kd_build_options(const RenderBenchOptions& o) {
  KdBuildOptions build;
  if (o.kd_intersect_cost >= 0) build.intersect_cost = o.kd_intersect_cost;
  if (o.kd_max_depth >= 0) build.max_depth = o.kd_max_depth;
  if (o.kd_leaf_prims >= 0) build.max_leaf_prims = o.kd_leaf_prims;
  return build;
}

}  // namespace

int bench_render_command(const RenderBenchOptions& o) {
  check_options(o);
  std::string note;
  const Backend backend = choose_backend(o.backend, &note);
  if (!note.empty()) std::printf("backend     %s\n", note.c_str());
  const std::unique_ptr<Renderer> renderer = make_renderer(backend == Backend::kCuda);
  const std::string date = utc_now("%Y-%m-%dT%H:%M:%SZ"), rev = git_revision();
  const int threads = omp_get_max_threads();

  // Scene; kd-tree built serially, then in parallel (the same tree).
  BenchScene b = make_bench_scene(o);
  std::printf("bench-render %s: %s, %d x %d, %d spp, %s\n", o.scene.c_str(), b.description.c_str(), o.width,
              o.height, o.spp, o.material.c_str());
  std::printf("device      %s [%s], %d host threads, %s, git %s\n", renderer->device_name().c_str(),
              backend_name(backend), threads, date.c_str(), rev.c_str());
  const KdBuildOptions build = kd_build_options(o);
  const TimedScene timed = make_timed_scene(b, o, build);
  const RenderScene& scene = timed.scene;
  const KdTreeStats& t = scene.tree.stats;

  // Render: one warm-up, then the best of `repeat`.
  const Camera camera = bench_camera(scene);
  const RenderTimes render = time_renders(*renderer, scene, camera, o);
  const RenderResult& first = render.first;
  const double best = render.best, total = render.total;
  const double primary_rate = double(first.rays) / best, all_rate = double(first.traced_rays) / best;
  std::printf(
      "render      best of %d %.4f s (mean %.4f s): primary %.3e rays/s, all rays %.3e rays/s (%.2f per "
      "primary)\n",
      o.repeat, best, total / o.repeat, primary_rate, all_rate,
      double(first.traced_rays) / double(first.rays));
  std::printf("per frame   scene and kd-tree rebuild %.3f s = %.1f x the render\n", timed.scene_seconds,
              timed.scene_seconds / best);

  // The same primary rays without shading on the host: the traversal alone.
  const CameraFrame frame = camera_frame(camera, o.width, o.height);
  const HostTrace host = trace_on_host(scene, frame, o.spp);
  const double host_rate = double(first.rays) / host.seconds;
  std::printf(
      "trace-only  host short-stack traversal of the primary rays, %d threads: %.3f s, %.3e rays/s; %.1f%% "
      "hit; "
      "%.1f nodes and %.1f primitive tests per ray\n",
      threads, host.seconds, host_rate, 100 * host.hit_fraction, host.nodes_per_ray, host.tests_per_ray);
  const std::string embree_json = embree_baseline(o, scene, frame, host, render, threads);
  const std::string two_level_json = two_level_comparison(o, b, scene, frame, build, first.rays);

  // Results file.
  ensure_directory(o.out);
  std::ostringstream js;
  js << "{\n  \"date\": \"" << date << "\",\n  \"git\": \"" << rev << "\",\n  \"device\": \""
     << json_escape(renderer->device_name()) << "\",\n  \"backend\": \"" << backend_name(backend)
     << "\",\n  \"host_threads\": " << threads << ",\n  \"workload\": \"" << o.scene
     << "\",\n  \"primitives\": " << scene.prims.size() << ",\n  \"width\": " << o.width
     << ",\n  \"height\": " << o.height << ",\n  \"spp\": " << o.spp << ",\n  \"material\": \"" << o.material
     << "\",\n  \"hidden_primitives\": " << scene.hidden
     << ",\n  \"scene_build_seconds\": " << timed.scene_seconds
     << ",\n  \"kd_tree\": {\"serial_build_seconds\": " << timed.serial_build
     << ", \"build_seconds\": " << t.build_seconds << ", \"build_threads\": " << t.threads
     << ", \"nodes\": " << t.nodes << ", \"depth\": " << t.depth << ", \"prim_refs\": " << t.prim_refs
     << "},\n  \"render\": {\"repeat\": " << o.repeat << ", \"best_seconds\": " << best
     << ", \"mean_seconds\": " << total / o.repeat << ", \"primary_rays\": " << first.rays
     << ", \"all_rays\": " << first.traced_rays << ", \"primary_rays_per_s\": " << primary_rate
     << ", \"all_rays_per_s\": " << all_rate << "},\n  \"host_trace\": {\"threads\": " << threads
     << ", \"seconds\": " << host.seconds << ", \"primary_rays_per_s\": " << host_rate
     << ", \"hit_fraction\": " << host.hit_fraction << ", \"nodes_per_ray\": " << host.nodes_per_ray
     << ", \"tests_per_ray\": " << host.tests_per_ray << "}" << embree_json << two_level_json << "\n}\n";
  const std::string file = o.out + "/" + utc_now("%Y%m%d-%H%M%S") + "_" + backend_name(backend) + "_render_" +
                           o.scene + "_" + std::to_string(scene.prims.size()) + ".json";
  write_file_atomic(file, js.str());
  std::printf("results     %s\n", file.c_str());
  return kExitOk;
}

}  // namespace pd
