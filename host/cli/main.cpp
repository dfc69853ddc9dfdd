// The perifrac command line: run a scene, benchmark the kernels, list devices.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/parallel/comm.h"
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
#include "host/app/run_folder.h"
#include "host/app/validate_command.h"
#include "host/io/atomic_file.h"
#include "host/scene/scene.h"

namespace pd {

namespace {

// Runs a subcommand: its exit code, or the one of the error it throws, reported in one line.
int report_errors(const std::function<int()>& action) {
  try {
    return action();
  } catch (const SceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResourceError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResumeError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const RunFolderError& e) {
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
}

// Makes `action` the subcommand's callback, run once the whole command line is parsed and
// checked; what it returns (report_errors) goes to *exit_code.
void on_parsed(CLI::App* cmd, int* exit_code, std::function<int()> action) {
  cmd->callback([exit_code, action = std::move(action)] { *exit_code = report_errors(action); });
}

// `perifrac run`: simulate a scene, or continue a run from its checkpoint.
void add_run(CLI::App& app, int* exit_code) {
  const auto run = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "simulate a scene and write per-frame output");
  cmd->add_option("scene", run->scene, "scene file (TOML); with --resume, the checkpoint's by default");
  cmd->add_option("--backend", run->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--set", run->overrides,
                  "KEY=VALUE: change a scene key for this run (repeatable), e.g. "
                  "--set materials.glass.bulk_modulus=2.94e8 --set projectiles[0].strength=1e8");
  cmd->add_option("--frames", run->frames, "number of frames (default: the scene's; 0: the set-up only)")
      ->check(CLI::Range(int64_t(0), kMaxFrames));
  cmd->add_option("--steps-per-frame", run->steps_per_frame, "steps per frame (default: the scene's)")
      ->check(CLI::Range(int64_t(1), kMaxStepsPerFrame));
  cmd->add_option("--out", run->out, "output folder (default: out/<scene name>)");
  CLI::Option* scale =
      cmd->add_option("--scale", run->scale, "particle-count factor, e.g. 0.05 for a small CPU run");
  cmd->add_flag("--allow-unstable-dt", run->allow_unstable_dt, "run even if dt exceeds the stable time step");
  cmd->add_flag("--explicit-families", run->explicit_families,
                "listed families for box-grid bodies too (what lattice families save, bench/NOTES.md)");
  cmd->add_option("--blend-frames", run->blend_frames,
                  "blend a split fragment's transform over N frames (0: off)")
      ->check(CLI::NonNegativeNumber);
  CLI::Option* every = cmd->add_option("--checkpoint-every", run->checkpoint_every,
                                       "write a checkpoint every N frames (0: off)")
                           ->check(CLI::NonNegativeNumber);
  CLI::Option* minutes =
      cmd->add_option("--checkpoint-minutes", run->checkpoint_minutes,
                      "write a checkpoint every M minutes of wall time (0: off; default 10)")
          ->check(CLI::NonNegativeNumber);
  CLI::Option* resume =
      cmd->add_option("--resume", run->resume, "continue the run in this output folder from its checkpoint");
  cmd->add_flag("--overwrite", run->overwrite,
                "replace the run the output folder holds (removes only that run's files)")
      ->excludes(resume);
  on_parsed(cmd, exit_code, [run, scale, every, minutes] {
    run->scale_given = scale->count() > 0;
    run->checkpoint_every_given = every->count() > 0;
    run->checkpoint_minutes_given = minutes->count() > 0;
    if (run->scene.empty() && run->resume.empty()) {
      std::fprintf(stderr, "error: run: give a scene file, or --resume DIR to continue a run\n");
      return int(kExitUsage);
    }
    return run_command(*run);
  });
}

// `perifrac bench`: time the step kernels.
void add_bench(CLI::App& app, int* exit_code) {
  const auto bench = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "time the step kernels (bond-updates/s, occupancy)");
  cmd->add_option("--scene", bench->scene, "scene file; default: a synthetic lattice cube");
  cmd->add_option("--scale", bench->scale, "scene particle-count factor");
  cmd->add_option("--lattice", bench->lattice, "lattice particles per side");
  cmd->add_option("--horizon", bench->horizon, "lattice delta / lambda");
  cmd->add_flag("--contact", bench->contact, "lattice: include collection + collisions");
  cmd->add_flag(
      "--explicit-families", bench->explicit_families,
      "find every partner through its stored index (box-grid bodies otherwise use lattice offsets)");
  cmd->add_option("--screen", bench->screen,
                  "springforces without the breaking path while no bond broke lately (auto), never "
                  "(off), or in every step (always)")
      ->check(CLI::IsMember({"auto", "off", "always"}));
  cmd->add_option("--model", bench->model,
                  "lattice material: bond_based | state_based | plastic | anisotropic")
      ->check(CLI::IsMember({"bond_based", "state_based", "plastic", "anisotropic"}));
  cmd->add_option("--backend", bench->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--steps", bench->steps, "timed steps");
  cmd->add_option("--warmup", bench->warmup, "untimed steps first");
  cmd->add_option("--out", bench->out, "results folder");
  on_parsed(cmd, exit_code, [bench] { return bench_command(*bench); });
}

// `perifrac bench-render`: time the raytracer on a synthetic scene.
void add_bench_render(CLI::App& app, int* exit_code) {
  const auto bench = std::make_shared<RenderBenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench-render", "time the raytracer on a synthetic scene (kd-tree build, rays/s, Embree baseline)");
  cmd->add_option("--scene", bench->scene, "slab (tetrahedra) | cubes | turned-cubes")
      ->check(CLI::IsMember({"slab", "cubes", "turned-cubes"}));
  cmd->add_option("--count", bench->count, "primitives wanted")->check(CLI::PositiveNumber);
  cmd->add_option("--width", bench->width, "image width")->check(CLI::Range(16, 16384));
  cmd->add_option("--height", bench->height, "image height")->check(CLI::Range(16, 16384));
  cmd->add_option("--spp", bench->spp, "samples per pixel")->check(CLI::Range(1, 1024));
  cmd->add_option("--material", bench->material, "opaque | glass")->check(CLI::IsMember({"opaque", "glass"}));
  cmd->add_option("--backend", bench->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--repeat", bench->repeat, "timed renders (the best counts)")->check(CLI::Range(1, 1000));
  cmd->add_flag("!--no-embree", bench->embree, "skip the Embree baseline");
  cmd->add_option("--fragments", bench->fragments,
                  "also time the two-level prototype with about this many moved fragments (0: no)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--kd-intersect-cost", bench->kd_intersect_cost,
                  "kd-tree SAH intersection cost (default 80)");
  cmd->add_option("--kd-max-depth", bench->kd_max_depth,
                  "kd-tree depth limit (default round(8 + 1.3 log2 N))");
  cmd->add_option("--kd-leaf-prims", bench->kd_leaf_prims,
                  "nodes with at most this many primitives become leaves (default 1)");
  cmd->add_flag("--keep-hidden", bench->keep_hidden,
                "put the tetrahedra no ray can reach first in the kd-tree too");
  cmd->add_option("--out", bench->out, "results folder");
  on_parsed(cmd, exit_code, [bench] { return bench_render_command(*bench); });
}

// `perifrac bench-geometry`: time making one body's particles.
void add_bench_geometry(CLI::App& app, int* exit_code) {
  const auto geometry = std::make_shared<GeometryBenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench-geometry", "time making one body's particles (grid, tets, shell, voronoi), stage by stage");
  cmd->add_option("--shape", geometry->shape, "sphere | vase | mesh")
      ->check(CLI::IsMember({"sphere", "vase", "mesh"}));
  cmd->add_option("--mesh", geometry->mesh, "with --shape mesh: an OBJ, PLY or STL file");
  cmd->add_option("--particles", geometry->particles, "grid | tets | shell | voronoi")
      ->check(CLI::IsMember({"grid", "tets", "shell", "voronoi"}));
  cmd->add_option("--count", geometry->count, "wanted particles (sets the spacing)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--spacing", geometry->spacing, "the spacing in m (overrides --count)");
  cmd->add_option("--tet-quality", geometry->tet_quality, "TetGen -q bound; 0 = no quality refinement");
  cmd->add_flag("--tet-keep-surface", geometry->tet_keep_surface,
                "TetGen -Y: no points added on the surface");
  cmd->add_option("--shell-thickness", geometry->shell_thickness, "vase wall / shell depth in m");
  cmd->add_option("--threads", geometry->threads, "threads of the parallel stages (0: default)");
  cmd->add_option("--seed", geometry->seed, "Poisson-disk seed");
  cmd->add_option("--csv", geometry->csv, "append a row to this CSV file");
  on_parsed(cmd, exit_code, [geometry] { return bench_geometry_command(*geometry); });
}

// `perifrac shapes`: write each body's solid as a mesh file.
void add_shapes(CLI::App& app, int* exit_code) {
  const auto shapes = std::make_shared<ShapeExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "shapes", "write each body's solid (procedural shape or checked mesh) as a mesh file");
  cmd->add_option("scene", shapes->scene, "scene file (.toml)")->required();
  cmd->add_option("--out", shapes->out, "folder for the files (default: shapes)");
  cmd->add_option("--format", shapes->format, "obj | ply | stl")->check(CLI::IsMember({"obj", "ply", "stl"}));
  cmd->add_option("--edge", shapes->edge,
                  "vertex spacing of curved surfaces in m (default: the body's spacing)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--set", shapes->overrides, "KEY=VALUE: change one scene key (repeatable)");
  on_parsed(cmd, exit_code, [shapes] { return export_shapes_command(*shapes); });
}

// `perifrac bench-fragments`: time the per-frame fragment outputs.
void add_bench_fragments(CLI::App& app, int* exit_code) {
  const auto fragments = std::make_shared<FragmentsBenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench-fragments", "time the per-frame fragment outputs (components, fits, crack and piece meshes)");
  cmd->add_option("--particles", fragments->particles, "grid | tets | voronoi")
      ->check(CLI::IsMember({"grid", "tets", "voronoi"}));
  cmd->add_option("--count", fragments->count, "wanted particles")
      ->check(CLI::Range(int64_t(8), int64_t(1) << 30));
  cmd->add_option("--horizon", fragments->horizon, "delta / lambda (0: 3 for grid and voronoi, 1.5 for tets)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--blocks", fragments->blocks, "the cut state has blocks^3 fragments")
      ->check(CLI::Range(2, 100));
  cmd->add_option("--frames", fragments->frames, "timed frames per state")->check(CLI::Range(2, 1000));
  cmd->add_option("--threads", fragments->threads, "OpenMP threads (0: default)");
  cmd->add_option("--out", fragments->out, "folder for the files (default: a temporary one, removed)");
  cmd->add_option("--csv", fragments->csv, "append rows to this CSV file");
  on_parsed(cmd, exit_code, [fragments] { return bench_fragments_command(*fragments); });
}

// `perifrac profile`: time per kernel in step ranges of a scene.
void add_profile(CLI::App& app, int* exit_code) {
  const auto profile = std::make_shared<ProfileOptions>();
  CLI::App* cmd = app.add_subcommand(
      "profile", "time per kernel in step ranges of a scene (before/during/after fracture)");
  cmd->add_option("scene", profile->scene, "scene file (TOML)")->required();
  cmd->add_option("--ranges", profile->ranges, "step ranges A:B,C:D (default: 5 equal ranges)");
  cmd->add_option("--steps", profile->steps, "steps to run (default: to the last range's end)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--timeline", profile->timeline, "timeline resolution in steps (default: ~100 points)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--scale", profile->scale, "scene particle-count factor");
  cmd->add_option("--backend", profile->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--out", profile->out, "results folder");
  on_parsed(cmd, exit_code, [profile] { return profile_command(*profile); });
}

// `perifrac validate`: run validation problems against known answers.
void add_validate(CLI::App& app, int* exit_code) {
  const auto validate = std::make_shared<ValidateOptions>();
  CLI::App* cmd =
      app.add_subcommand("validate", "run validation problems against analytic or published answers");
  cmd->add_option("--problem", validate->problem,
                  "all | wave_bar | tension_bar_pmb | tension_bar_lps | cantilever_pmb | "
                  "cantilever_lps | bar_twist_lps | bar_spin_lps | "
                  "crack_branching");
  cmd->add_option("--resolution", validate->resolutions,
                  "particles across, e.g. 4,6,8 (default: each problem's sweep)")
      ->delimiter(',');
  cmd->add_option("--delta-over-lambda", validate->delta_over_lambda, "horizon in spacings (default 3)");
  cmd->add_option("--dt-fraction", validate->dt_fraction, "dt / dt_c (default 0.5)");
  cmd->add_option("--backend", validate->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--csv", validate->csv, "append rows to this CSV");
  cmd->add_flag("--quiet", validate->quiet, "no per-row output");
  on_parsed(cmd, exit_code, [validate] { return validate_command(*validate); });
}

// `perifrac render`: render a run's frames to PNG.
void add_render(CLI::App& app, int* exit_code) {
  // The camera's points come as number lists, turned into the options' vectors after parsing.
  struct RenderArgs {
    RenderOptions options;
    std::vector<double> eye, look_at;
  };
  const auto render = std::make_shared<RenderArgs>();
  RenderOptions& o = render->options;
  CLI::App* cmd = app.add_subcommand("render", "render a run's frames to PNG (DIR/render/)");
  cmd->add_option("dir", o.dir, "output folder of `perifrac run`")->required();
  cmd->add_option("--out", o.out, "image folder (default: DIR/render)");
  cmd->add_option("--backend", o.backend, "auto | cpu | cuda")->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--width", o.width, "image width")->check(CLI::Range(16, 16384));
  cmd->add_option("--height", o.height, "image height")->check(CLI::Range(16, 16384));
  cmd->add_option("--spp", o.spp, "samples per pixel")->check(CLI::Range(1, 1024));
  cmd->add_option("--eye", render->eye, "camera position x,y,z (default: a 3/4 view of the rest box)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--look-at", render->look_at,
                  "point the camera looks at x,y,z (default: the rest box centre)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--vfov", o.vfov_degrees, "vertical field of view in degrees")
      ->check(CLI::Range(0.1, 179.9));
  cmd->add_option("--material", o.material, "opaque | glass: the material of every body")
      ->check(CLI::IsMember({"opaque", "glass"}));
  cmd->add_option("--ior", o.ior, "glass index of refraction")->check(CLI::Range(1.0, 4.0));
  cmd->add_option("--environment", o.environment,
                  "sky (procedural) or a Radiance .hdr latitude-longitude map");
  cmd->add_flag("!--no-movie", o.movie, "no movie.mp4 even when ffmpeg is on PATH");
  cmd->add_option("--frames", o.frames, "frame numbers to render, e.g. 20,60 (default: all; no movie)")
      ->delimiter(',')
      ->check(CLI::NonNegativeNumber);
  on_parsed(cmd, exit_code, [render] {
    const std::vector<double>& eye = render->eye;
    const std::vector<double>& look_at = render->look_at;
    if (eye.size() == 3) render->options.eye = Vec3{real(eye[0]), real(eye[1]), real(eye[2])};
    if (look_at.size() == 3)
      render->options.look_at = Vec3{real(look_at[0]), real(look_at[1]), real(look_at[2])};
    return render_frames(render->options);
  });
}

// `perifrac compare`: compare two output folders frame by frame.
void add_compare(CLI::App& app, int* exit_code) {
  const auto compare = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare", "compare two output folders frame by frame");
  cmd->add_option("a", compare->a, "first output folder")->required();
  cmd->add_option("b", compare->b, "second output folder")->required();
  cmd->add_option("--position-tolerance", compare->position_tolerance, "relative L2 of displacements");
  cmd->add_option("--damage-tolerance", compare->damage_tolerance, "mean absolute damage difference");
  on_parsed(cmd, exit_code, [compare] { return compare_command(*compare); });
}

// `perifrac info`: the backends this build and machine offer.
void add_info(CLI::App& app, int* exit_code) {
  CLI::App* cmd = app.add_subcommand("info", "show the backends this build and machine offer");
  on_parsed(cmd, exit_code, [] {
    std::string why;
    const bool gpu = cuda_device_available(&why);
    std::printf("perifrac %s\ncpu   available\ncuda  %s\n", PERIFRAC_VERSION,
                gpu ? "available" : why.c_str());
    return int(kExitOk);
  });
}

}  // namespace

}  // namespace pd

int main(int argc, char** argv) {
  using namespace pd;
  // Under mpirun, rank 0 runs the command and the engine's other ranks serve it
  // (cuda/parallel/partitioned_engine.h): they print nothing but errors.
  if (const auto world = world_comm()) {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command != "run" && command != "bench") {
      if (world->rank() == 0)
        std::fprintf(stderr,
                     "error: under mpirun only `perifrac run` and `perifrac bench` use the ranks; "
                     "start `perifrac %s` without mpirun\n",
                     command.c_str());
      return int(kExitUsage);
    }
    if (world->rank() != 0 && !std::freopen("/dev/null", "w", stdout)) return int(kExitRuntime);
  }
  CLI::App app{"perifrac: peridynamic fracture simulation on GPU and CPU"};
  app.set_version_flag("--version", std::string("perifrac ") + PERIFRAC_VERSION);
  app.require_subcommand(1);
  int exit_code = kExitOk;
  // In the order `perifrac --help` lists them.
  for (const auto add : {add_run, add_bench, add_bench_render, add_bench_geometry, add_shapes,
                         add_bench_fragments, add_profile, add_validate, add_render, add_compare, add_info})
    add(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // a command-line mistake: one line, exit code 2
    std::fprintf(stderr,
                 "error: %s (perifrac --help lists the commands, perifrac COMMAND --help the options)\n",
                 e.what());
    leave_world();
    return kExitUsage;
  }
  leave_world();
  return exit_code;
}
