// The perifrac command line: run a scene, benchmark the kernels, list devices.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "cuda/engine/engine.h"
#include "cuda/engine/memory_budget.h"
#include "host/app/bench.h"
#include "host/app/bench_fragments.h"
#include "host/app/bench_geometry.h"
#include "host/app/bench_render.h"
#include "host/app/checkpoint.h"
#include "host/app/compare.h"
#include "host/app/export_shapes.h"
#include "host/app/profile.h"
#include "host/app/render_frames.h"
#include "host/app/run.h"
#include "host/app/validate_command.h"
#include "host/io/atomic_file.h"
#include "host/scene/scene.h"

int main(int argc, char** argv) {
  using namespace pd;
  CLI::App app{"perifrac: peridynamic fracture simulation on GPU and CPU"};
  app.set_version_flag("--version", std::string("perifrac ") + PERIFRAC_VERSION);
  app.require_subcommand(1);

  RunOptions run;
  CLI::App* run_cmd = app.add_subcommand("run", "simulate a scene and write per-frame output");
  run_cmd->add_option("scene", run.scene, "scene file (TOML); with --resume, the checkpoint's by default");
  run_cmd->add_option("--backend", run.backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  run_cmd->add_option("--set", run.overrides,
                      "KEY=VALUE: change a scene key for this run (repeatable), e.g. "
                      "--set materials.glass.bulk_modulus=2.94e8 --set projectiles[0].strength=1e8");
  run_cmd->add_option("--frames", run.frames, "number of frames (default: the scene's)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--steps-per-frame", run.steps_per_frame, "steps per frame (default: the scene's)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--out", run.out, "output folder (default: out/<scene name>)");
  run_cmd->add_option("--scale", run.scale, "particle-count factor, e.g. 0.05 for a small CPU run");
  run_cmd->add_flag("--allow-unstable-dt", run.allow_unstable_dt,
                    "run even if dt exceeds the stable time step");
  run_cmd
      ->add_option("--blend-frames", run.blend_frames,
                   "blend a split fragment's transform over N frames (0: off)")
      ->check(CLI::NonNegativeNumber);
  run_cmd
      ->add_option("--checkpoint-every", run.checkpoint_every, "write a checkpoint every N frames (0: off)")
      ->check(CLI::NonNegativeNumber);
  run_cmd
      ->add_option("--checkpoint-minutes", run.checkpoint_minutes,
                   "write a checkpoint every M minutes of wall time (0: off; default 10)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--resume", run.resume, "continue the run in this output folder from its checkpoint");

  BenchOptions bench;
  CLI::App* bench_cmd = app.add_subcommand("bench", "time the step kernels (bond-updates/s, occupancy)");
  bench_cmd->add_option("--scene", bench.scene, "scene file; default: a synthetic lattice cube");
  bench_cmd->add_option("--scale", bench.scale, "scene particle-count factor");
  bench_cmd->add_option("--lattice", bench.lattice, "lattice particles per side");
  bench_cmd->add_option("--horizon", bench.horizon, "lattice delta / lambda");
  bench_cmd->add_flag("--contact", bench.contact, "lattice: include collection + collisions");
  bench_cmd->add_flag(
      "--explicit-families", bench.explicit_families,
      "find every partner through its stored index (box-grid bodies otherwise use lattice offsets)");
  bench_cmd
      ->add_option("--screen", bench.screen,
                   "springforces without the breaking path while no bond broke lately (auto), never "
                   "(off), or in every step (always)")
      ->check(CLI::IsMember({"auto", "off", "always"}));
  bench_cmd
      ->add_option("--model", bench.model,
                   "lattice material: bond_based | state_based | plastic | anisotropic")
      ->check(CLI::IsMember({"bond_based", "state_based", "plastic", "anisotropic"}));
  bench_cmd->add_option("--backend", bench.backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  bench_cmd->add_option("--steps", bench.steps, "timed steps");
  bench_cmd->add_option("--warmup", bench.warmup, "untimed steps first");
  bench_cmd->add_option("--out", bench.out, "results folder");

  RenderBenchOptions bench_render;
  CLI::App* bench_render_cmd = app.add_subcommand(
      "bench-render", "time the raytracer on a synthetic scene (kd-tree build, rays/s, Embree baseline)");
  bench_render_cmd->add_option("--scene", bench_render.scene, "slab (tetrahedra) | cubes | turned-cubes")
      ->check(CLI::IsMember({"slab", "cubes", "turned-cubes"}));
  bench_render_cmd->add_option("--count", bench_render.count, "primitives wanted")
      ->check(CLI::PositiveNumber);
  bench_render_cmd->add_option("--width", bench_render.width, "image width")->check(CLI::Range(16, 16384));
  bench_render_cmd->add_option("--height", bench_render.height, "image height")->check(CLI::Range(16, 16384));
  bench_render_cmd->add_option("--spp", bench_render.spp, "samples per pixel")->check(CLI::Range(1, 1024));
  bench_render_cmd->add_option("--material", bench_render.material, "opaque | glass")
      ->check(CLI::IsMember({"opaque", "glass"}));
  bench_render_cmd->add_option("--backend", bench_render.backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  bench_render_cmd->add_option("--repeat", bench_render.repeat, "timed renders (the best counts)")
      ->check(CLI::Range(1, 1000));
  bench_render_cmd->add_flag("!--no-embree", bench_render.embree, "skip the Embree baseline");
  bench_render_cmd
      ->add_option("--fragments", bench_render.fragments,
                   "also time the two-level prototype with about this many moved fragments (0: no)")
      ->check(CLI::NonNegativeNumber);
  bench_render_cmd->add_option("--kd-intersect-cost", bench_render.kd_intersect_cost,
                               "kd-tree SAH intersection cost (default 80)");
  bench_render_cmd->add_option("--kd-max-depth", bench_render.kd_max_depth,
                               "kd-tree depth limit (default round(8 + 1.3 log2 N))");
  bench_render_cmd->add_option("--kd-leaf-prims", bench_render.kd_leaf_prims,
                               "nodes with at most this many primitives become leaves (default 1)");
  bench_render_cmd->add_flag("--keep-hidden", bench_render.keep_hidden,
                             "put the tetrahedra no ray can reach first in the kd-tree too");
  bench_render_cmd->add_option("--out", bench_render.out, "results folder");

  RenderOptions render;
  ProfileOptions profile;
  GeometryBenchOptions geometry;
  CLI::App* geometry_cmd = app.add_subcommand(
      "bench-geometry", "time making one body's particles (grid, tets, shell, voronoi), stage by stage");
  geometry_cmd->add_option("--shape", geometry.shape, "sphere | vase | mesh")
      ->check(CLI::IsMember({"sphere", "vase", "mesh"}));
  geometry_cmd->add_option("--mesh", geometry.mesh, "with --shape mesh: an OBJ, PLY or STL file");
  geometry_cmd->add_option("--particles", geometry.particles, "grid | tets | shell | voronoi")
      ->check(CLI::IsMember({"grid", "tets", "shell", "voronoi"}));
  geometry_cmd->add_option("--count", geometry.count, "wanted particles (sets the spacing)")
      ->check(CLI::PositiveNumber);
  geometry_cmd->add_option("--spacing", geometry.spacing, "the spacing in m (overrides --count)");
  geometry_cmd->add_option("--tet-quality", geometry.tet_quality,
                           "TetGen -q bound; 0 = no quality refinement");
  geometry_cmd->add_flag("--tet-keep-surface", geometry.tet_keep_surface,
                         "TetGen -Y: no points added on the surface");
  geometry_cmd->add_option("--shell-thickness", geometry.shell_thickness, "vase wall / shell depth in m");
  geometry_cmd->add_option("--threads", geometry.threads, "threads of the parallel stages (0: default)");
  geometry_cmd->add_option("--seed", geometry.seed, "Poisson-disk seed");
  geometry_cmd->add_option("--csv", geometry.csv, "append a row to this CSV file");

  ShapeExportOptions shapes;
  CLI::App* shapes_cmd = app.add_subcommand(
      "shapes", "write each body's solid (procedural shape or checked mesh) as a mesh file");
  shapes_cmd->add_option("scene", shapes.scene, "scene file (.toml)")->required();
  shapes_cmd->add_option("--out", shapes.out, "folder for the files (default: shapes)");
  shapes_cmd->add_option("--format", shapes.format, "obj | ply | stl")
      ->check(CLI::IsMember({"obj", "ply", "stl"}));
  shapes_cmd
      ->add_option("--edge", shapes.edge,
                   "vertex spacing of curved surfaces in m (default: the body's spacing)")
      ->check(CLI::PositiveNumber);
  shapes_cmd->add_option("--set", shapes.overrides, "KEY=VALUE: change one scene key (repeatable)");

  FragmentsBenchOptions fragments;
  CLI::App* fragments_cmd = app.add_subcommand(
      "bench-fragments", "time the per-frame fragment outputs (components, fits, crack and piece meshes)");
  fragments_cmd->add_option("--particles", fragments.particles, "grid | tets | voronoi")
      ->check(CLI::IsMember({"grid", "tets", "voronoi"}));
  fragments_cmd->add_option("--count", fragments.count, "wanted particles")
      ->check(CLI::Range(int64_t(8), int64_t(1) << 30));
  fragments_cmd
      ->add_option("--horizon", fragments.horizon, "delta / lambda (0: 3 for grid and voronoi, 1.5 for tets)")
      ->check(CLI::NonNegativeNumber);
  fragments_cmd->add_option("--blocks", fragments.blocks, "the cut state has blocks^3 fragments")
      ->check(CLI::Range(2, 100));
  fragments_cmd->add_option("--frames", fragments.frames, "timed frames per state")
      ->check(CLI::Range(2, 1000));
  fragments_cmd->add_option("--threads", fragments.threads, "OpenMP threads (0: default)");
  fragments_cmd->add_option("--out", fragments.out,
                            "folder for the files (default: a temporary one, removed)");
  fragments_cmd->add_option("--csv", fragments.csv, "append rows to this CSV file");

  CLI::App* profile_cmd = app.add_subcommand(
      "profile", "time per kernel in step ranges of a scene (before/during/after fracture)");
  profile_cmd->add_option("scene", profile.scene, "scene file (TOML)")->required();
  profile_cmd->add_option("--ranges", profile.ranges, "step ranges A:B,C:D (default: 5 equal ranges)");
  profile_cmd->add_option("--steps", profile.steps, "steps to run (default: to the last range's end)")
      ->check(CLI::PositiveNumber);
  profile_cmd
      ->add_option("--timeline", profile.timeline, "timeline resolution in steps (default: ~100 points)")
      ->check(CLI::NonNegativeNumber);
  profile_cmd->add_option("--scale", profile.scale, "scene particle-count factor");
  profile_cmd->add_option("--backend", profile.backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  profile_cmd->add_option("--out", profile.out, "results folder");

  ValidateOptions validate;
  CLI::App* validate_cmd =
      app.add_subcommand("validate", "run validation problems against analytic or published answers");
  validate_cmd->add_option("--problem", validate.problem,
                           "all | wave_bar | tension_bar_pmb | tension_bar_lps | cantilever_pmb | "
                           "cantilever_lps | bar_twist_lps | bar_spin_lps | "
                           "crack_branching");
  validate_cmd
      ->add_option("--resolution", validate.resolutions,
                   "particles across, e.g. 4,6,8 (default: each problem's sweep)")
      ->delimiter(',');
  validate_cmd->add_option("--delta-over-lambda", validate.delta_over_lambda,
                           "horizon in spacings (default 3)");
  validate_cmd->add_option("--dt-fraction", validate.dt_fraction, "dt / dt_c (default 0.5)");
  validate_cmd->add_option("--backend", validate.backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  validate_cmd->add_option("--csv", validate.csv, "append rows to this CSV");
  validate_cmd->add_flag("--quiet", validate.quiet, "no per-row output");

  CLI::App* render_cmd = app.add_subcommand("render", "render a run's frames to PNG (DIR/render/)");
  render_cmd->add_option("dir", render.dir, "output folder of `perifrac run`")->required();
  render_cmd->add_option("--out", render.out, "image folder (default: DIR/render)");
  render_cmd->add_option("--backend", render.backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  render_cmd->add_option("--width", render.width, "image width")->check(CLI::Range(16, 16384));
  render_cmd->add_option("--height", render.height, "image height")->check(CLI::Range(16, 16384));
  render_cmd->add_option("--spp", render.spp, "samples per pixel")->check(CLI::Range(1, 1024));
  std::vector<double> eye, look_at;
  render_cmd->add_option("--eye", eye, "camera position x,y,z (default: a 3/4 view of the rest box)")
      ->delimiter(',')
      ->expected(3);
  render_cmd
      ->add_option("--look-at", look_at, "point the camera looks at x,y,z (default: the rest box centre)")
      ->delimiter(',')
      ->expected(3);
  render_cmd->add_option("--vfov", render.vfov_degrees, "vertical field of view in degrees")
      ->check(CLI::Range(0.1, 179.9));
  render_cmd->add_option("--material", render.material, "opaque | glass: the material of every body")
      ->check(CLI::IsMember({"opaque", "glass"}));
  render_cmd->add_option("--ior", render.ior, "glass index of refraction")->check(CLI::Range(1.0, 4.0));
  render_cmd->add_option("--environment", render.environment,
                         "sky (procedural) or a Radiance .hdr latitude-longitude map");
  render_cmd->add_flag("!--no-movie", render.movie, "no movie.mp4 even when ffmpeg is on PATH");
  render_cmd
      ->add_option("--frames", render.frames, "frame numbers to render, e.g. 20,60 (default: all; no movie)")
      ->delimiter(',')
      ->check(CLI::NonNegativeNumber);

  CompareOptions compare;
  CLI::App* compare_cmd = app.add_subcommand("compare", "compare two output folders frame by frame");
  compare_cmd->add_option("a", compare.a, "first output folder")->required();
  compare_cmd->add_option("b", compare.b, "second output folder")->required();
  compare_cmd->add_option("--position-tolerance", compare.position_tolerance, "relative L2 of displacements");
  compare_cmd->add_option("--damage-tolerance", compare.damage_tolerance, "mean absolute damage difference");

  CLI::App* info_cmd = app.add_subcommand("info", "show the backends this build and machine offer");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*run_cmd) {
      if (run.scene.empty() && run.resume.empty()) {
        std::fprintf(stderr, "error: run: give a scene file, or --resume DIR to continue a run\n");
        return kExitUsage;
      }
      return run_command(run);
    }
    if (*bench_cmd) return bench_command(bench);
    if (*geometry_cmd) return bench_geometry_command(geometry);
    if (*shapes_cmd) return export_shapes_command(shapes);
    if (*fragments_cmd) return bench_fragments_command(fragments);
    if (*bench_render_cmd) return bench_render_command(bench_render);
    if (*profile_cmd) return profile_command(profile);
    if (*validate_cmd) return validate_command(validate);
    if (*compare_cmd) return compare_command(compare);
    if (*render_cmd) {
      if (eye.size() == 3) render.eye = Vec3{real(eye[0]), real(eye[1]), real(eye[2])};
      if (look_at.size() == 3) render.look_at = Vec3{real(look_at[0]), real(look_at[1]), real(look_at[2])};
      return render_frames(render);
    }
    if (*info_cmd) {
      std::string why;
      const bool gpu = cuda_device_available(&why);
      std::printf("perifrac %s\ncpu   available\ncuda  %s\n", PERIFRAC_VERSION,
                  gpu ? "available" : why.c_str());
      return kExitOk;
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResourceError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResumeError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const IoError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRuntime;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRuntime;
  }
  return kExitOk;
}
