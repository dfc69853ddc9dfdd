#include "host/cli/command_line.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/geometry/tetgen.h"
#include "host/scene/scene.h"

namespace pd {

namespace {

// A finite number in [lo, hi]: CLI::Range lets NaN through (no comparison holds for it) and
// CLI::NonNegativeNumber prints its bound as 300 digits. `allowed` says what is, in the message.
CLI::Validator finite_in(double lo, double hi, const std::string& allowed) {
  return CLI::Validator(
      [lo, hi, allowed](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "not a number (allowed: " + allowed + ")";
        if (!std::isfinite(v) || v < lo || v > hi)
          return "value out of range (allowed: " + allowed + ")";  // (the value itself may be NaN)
        return {};
      },
      allowed);
}

// A folder or file name: not empty (an empty --out would quietly mean the default).
CLI::Validator non_empty() {
  return CLI::Validator(
      [](std::string& text) -> std::string { return text.empty() ? "an empty name (allowed: a path)" : ""; },
      "PATH");
}

// Each element of a number list (camera points): finite.
CLI::Validator finite_number() {
  return finite_in(-1e300, 1e300, "finite numbers");
}

// Makes `action` what *chosen runs once the whole command line is parsed and checked.
void on_parsed(CLI::App* cmd, std::function<int()>* chosen, std::function<int()> action) {
  cmd->callback([chosen, action = std::move(action)] { *chosen = action; });
}

// `perifrac run`: simulate a scene, or continue a run from its checkpoint.
void add_run(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
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
  cmd->add_option("--out", run->out, "output folder (default: out/<scene name>)")->check(non_empty());
  CLI::Option* scale = cmd->add_option("--scale", run->scale,
                                       "particle-count factor in (0, 1000], e.g. 0.05 for a small CPU run");
  cmd->add_flag("--allow-unstable-dt", run->allow_unstable_dt, "run even if dt exceeds the stable time step");
  cmd->add_flag("--explicit-families", run->explicit_families,
                "listed families for box-grid bodies too (what lattice families save, bench/NOTES.md)");
  cmd->add_option("--blend-frames", run->blend_frames,
                  "blend a split fragment's transform over N frames (0: off)")
      ->check(CLI::Range(0, 1000000));
  CLI::Option* every = cmd->add_option("--checkpoint-every", run->checkpoint_every,
                                       "write a checkpoint every N frames (0: off)")
                           ->check(CLI::Range(int64_t(0), kMaxFrames));
  CLI::Option* minutes =
      cmd->add_option("--checkpoint-minutes", run->checkpoint_minutes,
                      "write a checkpoint every M minutes of wall time (0: off; default 10)")
          ->check(finite_in(0, 1e6, "0 (off) or minutes up to 1e6"));
  CLI::Option* resume =
      cmd->add_option("--resume", run->resume, "continue the run in this output folder from its checkpoint");
  cmd->add_flag("--overwrite", run->overwrite,
                "replace the run the output folder holds (removes only that run's files)")
      ->excludes(resume);
  on_parsed(cmd, chosen, [&actions, run, scale, every, minutes] {
    run->scale_given = scale->count() > 0;
    run->checkpoint_every_given = every->count() > 0;
    run->checkpoint_minutes_given = minutes->count() > 0;
    if (run->scene.empty() && run->resume.empty()) {
      std::fprintf(stderr, "error: run: give a scene file, or --resume DIR to continue a run\n");
      return int(kExitUsage);
    }
    return actions.run(*run);
  });
}

// `perifrac bench`: time the step kernels.
void add_bench(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto bench = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "time the step kernels (bond-updates/s, occupancy)");
  CLI::Option* scene =
      cmd->add_option("--scene", bench->scene, "scene file; default: a synthetic lattice cube");
  cmd->add_option("--scale", bench->scale, "scene particle-count factor in (0, 1000]");
  cmd->add_option("--set", bench->overrides, "KEY=VALUE: change one scene key (repeatable)");
  // The lattice's options describe the synthetic cube: with --scene they would do nothing.
  cmd->add_option("--lattice", bench->lattice, "lattice particles per side")
      ->check(CLI::Range(int64_t(4), int64_t(1000)))
      ->excludes(scene);
  cmd->add_option("--horizon", bench->horizon, "lattice delta / lambda")
      ->check(finite_in(1, 20, "a horizon of 1 to 20 spacings"))
      ->excludes(scene);
  cmd->add_flag("--contact", bench->contact, "lattice: include collection + collisions")->excludes(scene);
  cmd->add_flag(
      "--explicit-families", bench->explicit_families,
      "find every partner through its stored index (box-grid bodies otherwise use lattice offsets)");
  cmd->add_option("--screen", bench->screen,
                  "springforces without the breaking path while no bond broke lately (auto), never "
                  "(off), or in every step (always)")
      ->check(CLI::IsMember({"auto", "off", "always"}));
  cmd->add_option("--bond-threads", bench->bond_threads,
                  "threads per particle in the GPU's bond loops: 1, 4, 8, 16, 32, or 0 to "
                  "choose from the scene (cuda/team.h)")
      ->check(CLI::IsMember({0, 1, 4, 8, 16, 32}));
  cmd->add_option("--step-graphs", bench->step_graphs,
                  "the step as CUDA graphs of 32 steps where no host work falls between its launches: "
                  "in scenes below 524,288 particles (auto), in any (on), or never (off: per-kernel times)")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_option("--contact-rebuild", bench->contact_rebuild,
                  "contact lists rebuilt for just the particles that left their skins where they are "
                  "few (incremental), or all at every build (full); the forces are the same")
      ->check(CLI::IsMember({"incremental", "full"}));
  cmd->add_option("--model", bench->model,
                  "lattice material: bond_based | state_based | plastic | anisotropic")
      ->check(CLI::IsMember({"bond_based", "state_based", "plastic", "anisotropic"}))
      ->excludes(scene);
  cmd->add_option("--backend", bench->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--steps", bench->steps, "timed steps")->check(CLI::Range(int64_t(1), int64_t(1) << 40));
  cmd->add_option("--warmup", bench->warmup, "untimed steps first")
      ->check(CLI::Range(int64_t(0), int64_t(1) << 40));
  cmd->add_flag("--allow-unstable-dt", bench->allow_unstable_dt,
                "time the steps even if dt exceeds the stable time step");
  cmd->add_option("--out", bench->out, "results folder")->check(non_empty());
  on_parsed(cmd, chosen, [&actions, bench] { return actions.bench(*bench); });
}

// `perifrac bench-render`: time the raytracer on a synthetic scene.
void add_bench_render(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto bench = std::make_shared<RenderBenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench-render", "time the raytracer on a synthetic scene (kd-tree build, rays/s, Embree baseline)");
  cmd->add_option("--scene", bench->scene, "slab (tetrahedra) | cubes | turned-cubes")
      ->check(CLI::IsMember({"slab", "cubes", "turned-cubes"}));
  cmd->add_option("--count", bench->count, "primitives wanted")
      ->check(CLI::Range(int64_t(1), int64_t(1) << 31));
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
      ->check(CLI::Range(0, 1 << 24));
  cmd->add_option("--kd-intersect-cost", bench->kd_intersect_cost,
                  "kd-tree SAH intersection cost (default 80)")
      ->check(finite_in(1e-3, 1e6, "a cost from 1e-3 to 1e6"));
  cmd->add_option("--kd-max-depth", bench->kd_max_depth,
                  "kd-tree depth limit (default round(8 + 1.3 log2 N))")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--kd-leaf-prims", bench->kd_leaf_prims,
                  "nodes with at most this many primitives become leaves (default 1)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_flag("--keep-hidden", bench->keep_hidden,
                "put the tetrahedra no ray can reach first in the kd-tree too");
  cmd->add_option("--out", bench->out, "results folder")->check(non_empty());
  on_parsed(cmd, chosen, [&actions, bench] { return actions.bench_render(*bench); });
}

// `perifrac bench-geometry`: time making one body's particles.
void add_bench_geometry(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto geometry = std::make_shared<GeometryBenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench-geometry", "time making one body's particles (grid, tets, shell, voronoi), stage by stage");
  cmd->add_option("--shape", geometry->shape, "sphere | vase | mesh")
      ->check(CLI::IsMember({"sphere", "vase", "mesh"}));
  cmd->add_option("--mesh", geometry->mesh, "with --shape mesh: an OBJ, PLY or STL file");
  cmd->add_option("--particles", geometry->particles, "grid | tets | shell | voronoi")
      ->check(CLI::IsMember({"grid", "tets", "shell", "voronoi"}));
  cmd->add_option("--count", geometry->count, "wanted particles (sets the spacing)")
      ->check(CLI::Range(int64_t(1), int64_t(1) << 31));
  cmd->add_option("--spacing", geometry->spacing, "the spacing in m (overrides --count)")
      ->check(finite_in(1e-6, 1e3, "a spacing from 1e-6 to 1e3 m"));
  cmd->add_option("--tet-quality", geometry->tet_quality, "TetGen -q bound; 0 = no quality refinement")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {  // as the scene key tet_quality
            double q = -1;
            if (CLI::detail::lexical_cast(text, q) && tet_quality_allowed(q)) return {};
            return std::string("value out of range (allowed: ") + kTetQualityAllowed + ")";
          },
          "0 or [1.1, 10]"));
  cmd->add_flag("--tet-keep-surface", geometry->tet_keep_surface,
                "TetGen -Y: no points added on the surface");
  cmd->add_option("--shell-thickness", geometry->shell_thickness, "vase wall / shell depth in m");
  cmd->add_option("--threads", geometry->threads, "threads of the parallel stages (0: default)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--seed", geometry->seed, "Poisson-disk seed");
  cmd->add_option("--csv", geometry->csv, "append a row to this CSV file")->check(non_empty());
  on_parsed(cmd, chosen, [&actions, geometry] { return actions.bench_geometry(*geometry); });
}

// `perifrac shapes`: write each body's solid as a mesh file.
void add_shapes(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto shapes = std::make_shared<ShapeExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "shapes", "write each body's solid (procedural shape or checked mesh) as a mesh file");
  cmd->add_option("scene", shapes->scene, "scene file (.toml)")->required();
  cmd->add_option("--out", shapes->out, "folder for the files (default: shapes)")->check(non_empty());
  cmd->add_option("--format", shapes->format, "obj | ply | stl")->check(CLI::IsMember({"obj", "ply", "stl"}));
  cmd->add_option("--edge", shapes->edge,
                  "vertex spacing of curved surfaces in m (default: the body's spacing)")
      ->check(finite_in(1e-6, 1e3, "an edge from 1e-6 to 1e3 m"));
  cmd->add_option("--set", shapes->overrides, "KEY=VALUE: change one scene key (repeatable)");
  on_parsed(cmd, chosen, [&actions, shapes] { return actions.shapes(*shapes); });
}

// `perifrac bench-fragments`: time the per-frame fragment outputs.
void add_bench_fragments(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto fragments = std::make_shared<FragmentsBenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench-fragments", "time the per-frame fragment outputs (components, fits, crack and piece meshes)");
  cmd->add_option("--particles", fragments->particles, "grid | tets | voronoi")
      ->check(CLI::IsMember({"grid", "tets", "voronoi"}));
  cmd->add_option("--count", fragments->count, "wanted particles")
      ->check(CLI::Range(int64_t(8), int64_t(1) << 30));
  cmd->add_option("--horizon", fragments->horizon, "delta / lambda (0: 3 for grid and voronoi, 1.5 for tets)")
      ->check(finite_in(0, 20, "0 (the default) or a horizon up to 20 spacings"));
  cmd->add_option("--blocks", fragments->blocks, "the cut state has blocks^3 fragments")
      ->check(CLI::Range(2, 100));
  cmd->add_option("--frames", fragments->frames, "timed frames per state")->check(CLI::Range(2, 1000));
  cmd->add_option("--threads", fragments->threads, "OpenMP threads (0: default)")->check(CLI::Range(0, 4096));
  cmd->add_option("--out", fragments->out, "folder for the files (default: a temporary one, removed)")
      ->check(non_empty());
  cmd->add_option("--csv", fragments->csv, "append rows to this CSV file")->check(non_empty());
  on_parsed(cmd, chosen, [&actions, fragments] { return actions.bench_fragments(*fragments); });
}

// `perifrac profile`: time per kernel in step ranges of a scene.
void add_profile(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto profile = std::make_shared<ProfileOptions>();
  CLI::App* cmd = app.add_subcommand(
      "profile", "time per kernel in step ranges of a scene (before/during/after fracture)");
  cmd->add_option("scene", profile->scene, "scene file (TOML)")->required();
  cmd->add_option("--ranges", profile->ranges, "step ranges A:B,C:D (default: 5 equal ranges)");
  cmd->add_option("--steps", profile->steps, "steps to run (default: to the last range's end)")
      ->check(CLI::Range(int64_t(1), int64_t(1) << 40));
  cmd->add_option("--timeline", profile->timeline, "timeline resolution in steps (default: ~100 points)")
      ->check(CLI::Range(int64_t(0), int64_t(1) << 40));
  cmd->add_option("--scale", profile->scale, "scene particle-count factor in (0, 1000]");
  cmd->add_option("--backend", profile->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--out", profile->out, "results folder")->check(non_empty());
  on_parsed(cmd, chosen, [&actions, profile] { return actions.profile(*profile); });
}

// `perifrac validate`: run validation problems against known answers.
void add_validate(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto validate = std::make_shared<ValidateOptions>();
  CLI::App* cmd =
      app.add_subcommand("validate", "run validation problems against analytic or published answers");
  cmd->add_option("--problem", validate->problem,
                  "all | wave_bar | tension_bar_pmb | tension_bar_lps | cantilever_pmb | "
                  "cantilever_lps | bar_twist_lps | bar_spin_lps | "
                  "crack_branching | notched_bar_pmb | crack_tip_pmb");
  cmd->add_option("--resolution", validate->resolutions,
                  "particles across, e.g. 4,6,8 (default: each problem's sweep)")
      ->delimiter(',');
  cmd->add_option("--delta-over-lambda", validate->delta_over_lambda, "horizon in spacings (default 3)")
      ->check(finite_in(1, 10, "a horizon of 1 to 10 spacings"));
  cmd->add_option("--dt-fraction", validate->dt_fraction,
                  "dt / dt_c (default 0.5; 0.3 with --surface-correction ghosts, whose bonds shorten the "
                  "stable step: a fraction past the step measured on the engine is refused)")
      ->check(finite_in(1e-6, 1, "a fraction of the critical step dt_c, > 0 and at most 1"));
  cmd->add_option("--backend", validate->backend, "auto | cpu | cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--surface-correction", validate->surface,
                  "default | on | off | ghosts: the surface correction (default: each model's, on for "
                  "bond-based, off for state-based; ghosts: the ghost correction)")
      ->check(CLI::IsMember({"default", "on", "off", "ghosts"}));
  cmd->add_option("--particles", validate->particles,
                  "grid | voronoi | tets: the bar's particles (default grid; voronoi and tets in the tension "
                  "bars only)")
      ->check(CLI::IsMember({"grid", "voronoi", "tets"}));
  cmd->add_option(
      "--traction", validate->traction_mpa,
      "crack_branching only: the step traction on the plate's edges in MPa (default 3.04, 0.35 E s0 at "
      "delta = 3 mm, the same at every resolution)");
  cmd->add_option("--csv", validate->csv, "append rows to this CSV")->check(non_empty());
  cmd->add_flag("--quiet", validate->quiet, "no per-row output");
  on_parsed(cmd, chosen, [&actions, validate] { return actions.validate(*validate); });
}

// `perifrac render`: render a run's frames to PNG.
void add_render(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  // The camera's points come as number lists, turned into the options' vectors after parsing.
  struct RenderArgs {
    RenderOptions options;
    std::vector<double> eye, look_at;
    bool no_movie = false;
  };
  const auto render = std::make_shared<RenderArgs>();
  RenderOptions& o = render->options;
  CLI::App* cmd = app.add_subcommand("render", "render a run's frames to PNG (DIR/render/)");
  cmd->add_option("dir", o.dir, "output folder of `perifrac run`")->required();
  cmd->add_option("--out", o.out, "image folder (default: DIR/render)")->check(non_empty());
  cmd->add_option("--backend", o.backend, "auto | cpu | cuda")->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--width", o.width, "image width")->check(CLI::Range(16, 16384));
  cmd->add_option("--height", o.height, "image height")->check(CLI::Range(16, 16384));
  cmd->add_option("--spp", o.spp, "samples per pixel")->check(CLI::Range(1, 1024));
  cmd->add_option("--eye", render->eye, "camera position x,y,z (default: a 3/4 view of the rest box)")
      ->check(finite_number())
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--look-at", render->look_at,
                  "point the camera looks at x,y,z (default: the rest box centre)")
      ->check(finite_number())
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--vfov", o.vfov_degrees, "vertical field of view in degrees")
      ->check(finite_in(0.1, 179.9, "degrees from 0.1 to 179.9"));
  cmd->add_option("--material", o.material,
                  "opaque | glass: the material of every body (replaces the scene's looks)")
      ->check(CLI::IsMember({"opaque", "glass"}));
  cmd->add_flag("--damage-colors", o.damage_colors, "tint damaged particles red");
  cmd->add_option("--surface", o.surface,
                  "elements | mesh: draw every particle as its element (default), or the bodies from "
                  "each frame's crack mesh (crack_mesh_NNNNN.ply, which the run must have written), "
                  "smooth-shaded")
      ->check(CLI::IsMember({"elements", "mesh"}));
  cmd->add_option("--smooth-cracks", o.smooth_cracks,
                  "Taubin smoothing passes over the crack surfaces with --surface mesh (default 2; 0: "
                  "the element faces as they are)")
      ->check(CLI::Range(0, 100));
  cmd->add_option("--ior", o.ior, "glass index of refraction")->check(finite_in(1, 4, "1 to 4"));
  cmd->add_option("--environment", o.environment,
                  "sky (procedural) or a Radiance .hdr latitude-longitude map");
  cmd->add_flag("--no-movie", render->no_movie, "no movie.mp4 even when ffmpeg is on PATH");
  cmd->add_option("--frames", o.frames, "frame numbers to render, e.g. 20,60 (default: all; no movie)")
      ->delimiter(',')
      ->check(CLI::Range(int64_t(0), kMaxFrames));
  // What the command line gave, noted when parsing ends; the rest comes from the run's scene's
  // [render] block, if any (render_frames).
  cmd->parse_complete_callback([render, cmd] {
    for (const CLI::Option* opt : cmd->get_options())
      if (opt->count() > 0 && !opt->get_lnames().empty())
        render->options.given.push_back("--" + opt->get_lnames().front());
  });
  on_parsed(cmd, chosen, [&actions, render] {
    const std::vector<double>& eye = render->eye;
    const std::vector<double>& look_at = render->look_at;
    render->options.movie = !render->no_movie;
    if (eye.size() == 3) render->options.eye = Vec3{real(eye[0]), real(eye[1]), real(eye[2])};
    if (look_at.size() == 3)
      render->options.look_at = Vec3{real(look_at[0]), real(look_at[1]), real(look_at[2])};
    return actions.render(render->options);
  });
}

// `perifrac compare`: compare two output folders frame by frame.
void add_compare(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  const auto compare = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare", "compare two output folders frame by frame");
  cmd->add_option("a", compare->a, "first output folder")->required();
  cmd->add_option("b", compare->b, "second output folder")->required();
  cmd->add_option("--position-tolerance", compare->position_tolerance, "relative L2 of displacements")
      ->check(finite_in(0, 1e6, "a tolerance >= 0"));
  cmd->add_option("--damage-tolerance", compare->damage_tolerance, "mean absolute damage difference")
      ->check(finite_in(0, 1, "a tolerance from 0 to 1"));
  on_parsed(cmd, chosen, [&actions, compare] { return actions.compare(*compare); });
}

// `perifrac info`: the backends this build and machine offer.
void add_info(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  CLI::App* cmd = app.add_subcommand("info", "show the backends this build and machine offer");
  on_parsed(cmd, chosen, [&actions] { return actions.info(); });
}

}  // namespace

void add_commands(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen) {
  app.set_version_flag("--version", std::string("perifrac ") + PERIFRAC_VERSION);
  app.require_subcommand(1);
  for (const auto add : {add_run, add_bench, add_bench_render, add_bench_geometry, add_shapes,
                         add_bench_fragments, add_profile, add_validate, add_render, add_compare, add_info})
    add(app, actions, chosen);
}

std::string unknown_command_error(const CLI::App& app, const std::string& first) {
  if (first.empty() || first[0] == '-') return {};
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == first) return {};
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  std::string line = "error: unknown command '" + first + "' (allowed: " + names + "; perifrac --help)";
  for (char& c : line)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return line;
}

std::string command_line_error(const CLI::ParseError& e) {
  std::string line = std::string("error: ") + e.what() +
                     " (perifrac --help lists the commands, perifrac COMMAND --help the options)";
  for (char& c : line)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return line;
}

}  // namespace pd
