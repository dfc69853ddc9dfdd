#include "host/app/run.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/parallel/comm.h"
#include "host/app/backend_choice.h"
#include "host/app/checkpoint.h"
#include "host/app/energy_watch.h"
#include "host/app/kernel_report.h"
#include "host/app/run_folder.h"
#include "host/app/run_output.h"
#include "host/app/shards_pattern.h"
#include "host/app/time_step_check.h"
#include "host/fragments/tet_file.h"
#include "host/fragments/trimtope_file.h"
#include "host/geometry/stage_time.h"
#include "host/io/atomic_file.h"
#include "host/io/frame_file.h"
#include "host/io/interrupt.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

namespace {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0 || seconds > 3.6e8) return "--:--";  // (beyond 100,000 hours)
  const long s = std::lround(seconds);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

// Start-up report: what the scene became.
void print_setup(const Scene& scene, const SetupResult& setup, const RunOptions& opt) {
  std::printf("scene      %s%s%s\n", scene.path.c_str(), scene.description.empty() ? "" : " - ",
              scene.description.c_str());
  for (const std::string& o : opt.overrides) std::printf("set        %s\n", o.c_str());
  std::printf("particles  %zu in %zu bodies (scale %g)\n", setup.input.particles.size(), scene.bodies.size(),
              opt.scale);
  for (size_t k = 0; k < setup.materials.size(); ++k) {
    const MaterialSummary& m = setup.materials[k];
    const Material& km = setup.input.materials.m[k];
    char model[160];
    if (km.model == kStateBased)
      std::snprintf(model, sizeof model, "state-based K %.4g Pa, mu %.4g Pa%s%s", double(km.bulk_modulus),
                    double(km.shear_modulus), km.plastic ? ", plastic" : "",
                    km.anisotropic ? ", anisotropic" : "");
    else
      std::snprintf(model, sizeof model, "bond-based c %.4g N/m^6", m.micromodulus);
    std::printf(
        "material   '%s' on body '%s': %s; lambda %.4g m, delta %.4g m, strain limit %.4g, dt_c %.3g s\n",
        m.name.c_str(), m.body.c_str(), model, m.spacing, m.horizon, m.strain_limit, m.critical_dt);
  }
  std::printf("time step  dt %.4g s = %.2f dt_c (continuum estimate)%s; %lld steps per frame\n", setup.dt,
              setup.dt / setup.critical_dt, scene.dt_auto ? ", chosen by dt = \"auto\"" : "",
              (long long)scene.steps_per_frame);
}

RestData rest_data(const ParticleSet& ps) {
  RestData r;
  r.position = ps.rest;
  r.volume.assign(ps.volume.begin(), ps.volume.end());
  r.body = ps.body;
  r.material.assign(ps.material.begin(), ps.material.end());
  return r;
}

// The scene of checkpoint `c` in folder `dir`: at its absolute path, else where it lies relative to
// the folder (the scene and the run moved together); the scene's hash checks it either way.
std::string checkpoint_scene(const RunCheckpoint& c, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(c.scene_path, ec)) return c.scene_path;
  const std::string beside = c.scene_relative.empty() ? "" : (fs::path(dir) / c.scene_relative).string();
  if (!beside.empty() && fs::exists(beside, ec)) {
    std::printf("resume     the scene is not at '%s' any more: using '%s' (found relative to the run)\n",
                c.scene_path.c_str(), beside.c_str());
    return beside;
  }
  throw ResumeError("cannot resume: the checkpoint's scene '" + c.scene_path + "' is gone" +
                    (beside.empty() ? "" : " (nor at '" + beside + "', relative to the run)") +
                    "; give it: perifrac run SCENE --resume " + dir);
}

// Reads the checkpoint of `opt.resume` and takes over what the run was started with: the scene
// (unless given again), backend (unless given), scale, steps per frame, blending, and the frame
// count unless --frames extends it.
RunCheckpoint open_resume(RunOptions& opt) {
  const std::string path = opt.resume + "/" + kCheckpointFileName;
  if (!std::filesystem::exists(path))
    throw ResumeError(
        "cannot resume from '" + opt.resume + "': it holds no " + kCheckpointFileName +
        " (the run wrote none: checkpoints are written every --checkpoint-minutes, every "
        "--checkpoint-every N frames and on Ctrl-C; or this is not a run's output folder); "
        "start the run again with --overwrite instead of --resume, and --checkpoint-every N to extend it "
        "later");
  RunCheckpoint c;
  try {
    c = read_checkpoint(path);
  } catch (const IoError& e) {
    throw ResumeError(std::string(e.what()) + "; start the run again with --overwrite instead of --resume");
  }
  if (opt.scene.empty()) opt.scene = checkpoint_scene(c, opt.resume);
  if (opt.overrides.empty()) opt.overrides = c.overrides;
  if (!opt.out.empty() && opt.out != opt.resume)
    throw ResumeError("--out '" + opt.out + "' and --resume '" + opt.resume +
                      "' differ: a resumed run continues in its own folder");
  opt.out = opt.resume;
  if (opt.backend == "auto") opt.backend = c.backend;  // bit for bit needs the same backend
  if (opt.scale_given && opt.scale != c.scale)
    throw ResumeError("--scale " + format_number(opt.scale) + " differs from the " + format_number(c.scale) +
                      " of the checkpointed run: a resumed run keeps its particles (leave --scale out)");
  opt.scale = c.scale;
  if (!opt.checkpoint_every_given) opt.checkpoint_every = c.checkpoint_every;
  if (!opt.checkpoint_minutes_given) opt.checkpoint_minutes = c.checkpoint_minutes;
  opt.blend_frames = c.blend_frames;
  opt.allow_unstable_dt = opt.allow_unstable_dt || c.allow_unstable_dt;
  if (opt.explicit_families != c.explicit_families && opt.explicit_families)
    throw ResumeError("--explicit-families was not given to the checkpointed run");
  opt.explicit_families = c.explicit_families;
  if (opt.steps_per_frame >= 1 && opt.steps_per_frame != c.steps_per_frame)
    throw ResumeError("--steps-per-frame " + std::to_string(opt.steps_per_frame) + " differs from the " +
                      std::to_string(c.steps_per_frame) + " of the checkpointed run");
  opt.steps_per_frame = c.steps_per_frame;
  if (opt.frames < 0) opt.frames = c.frames;
  return c;
}

// A resume continues from its checkpoint and removes the frames written after it: where the run
// went on past its checkpoint (a checkpoint every N frames, or one left by an interrupted run that
// was resumed to its end), ending before its last frame would lose frames. Refused; ending at it or
// past it writes those frames again, the same bits.
void check_resume_target(const RunCheckpoint& c, const RunManifest& m, int64_t frames,
                         const std::string& dir) {
  if (m.frames_written <= c.frame || frames >= m.frames_written) return;
  throw ResumeError("cannot resume '" + dir + "' to frame " + std::to_string(frames) +
                    ": it holds frames 0 to " + std::to_string(m.frames_written) +
                    " and its checkpoint is after frame " + std::to_string(c.frame) + ", so frames " +
                    std::to_string(frames + 1) + " to " + std::to_string(m.frames_written) +
                    " would be removed; pass --frames N with N >= " + std::to_string(m.frames_written));
}

// The checkpoint must come from this scene file and set-up; the backend may differ (the run
// continues, no longer bit for bit).
void check_resume(const RunCheckpoint& c, const Scene& scene, const std::vector<std::string>& overrides,
                  const SetupResult& setup, Backend backend) {
  if (scene_fingerprint(scene.path, overrides) != c.scene_hash)
    throw ResumeError("cannot resume: the scene file '" + scene.path +
                      "' or its --set overrides are not the ones the checkpoint was written from (the file "
                      "changed, or another scene or other overrides were given)");
  if (setup_fingerprint(setup.input) != c.setup_hash)
    throw ResumeError("cannot resume: set-up of '" + scene.path +
                      "' no longer gives the checkpoint's particles (a mesh or the seed changed)");
  if (c.backend != backend_name(backend))
    std::printf("resume     checkpoint written on %s, continuing on %s: results are not bit-identical\n",
                c.backend.c_str(), backend_name(backend));
}

// What set-up made of the scene: the scene as run, its particles, the backend and the engine.
struct Simulation {
  Scene scene;
  Backend backend = Backend::kCpu;
  SetupResult setup;
  std::unique_ptr<Engine> engine;
  std::vector<StageTime> stages;      // the set-up's stages and their wall times, in order
  std::optional<double> measured_dt;  // with ghosts, the stable step measured on the engine
};

// Loads the scene with the run's options, makes its particles and reports them; checks the time
// step and, for a resumed run, that the checkpoint comes from this scene and set-up.
Simulation set_up_simulation(const RunOptions& opt, const std::optional<RunCheckpoint>& resume) {
  Simulation sim;
  StageClock clock(&sim.stages);
  Scene& scene = sim.scene;
  scene = load_scene(opt.scene, opt.overrides);
  if (opt.frames >= 0) scene.frames = opt.frames;
  if (opt.steps_per_frame >= 1) scene.steps_per_frame = opt.steps_per_frame;
  clock.lap("scene file");
  // The backend and the particle budget on a thread of their own (on a GPU its driver starts
  // there), waited for where the set-up first needs them: beside a tet body's TetGen. (A run over
  // MPI ranks finds them first, on the thread that started MPI.)
  std::string note;
  if (world_comm()) {
    sim.backend = choose_backend(opt.backend, &note);
    clock.lap("backend");
    sim.setup = setup_scene_with_patterns(scene, opt.scale, sim.backend);
  } else {
    const std::shared_future<Backend> backend =
        std::async(std::launch::async, [&opt, &note] { return choose_backend(opt.backend, &note); }).share();
    sim.setup = setup_scene_with_patterns(scene, setup_options_later(scene, opt.scale, backend));
    sim.backend = backend.get();
  }
  clock.lap("particles");
  split_last_stage(sim.stages, sim.setup.stages, "", "particles");
  print_setup(scene, sim.setup, opt);
  check_time_step(scene, sim.setup, opt.allow_unstable_dt);
  if (!note.empty()) std::printf("backend    %s\n", note.c_str());
  if (resume) check_resume(*resume, scene, opt.overrides, sim.setup, sim.backend);
  return sim;
}

// The set-up's stages on one line, those under 10 ms summed as "others".
void print_setup_stages(const std::vector<StageTime>& stages) {
  double total = 0, others = 0;
  std::string line;
  char buf[64];
  for (const StageTime& s : stages) {
    total += s.seconds;
    if (s.seconds < 0.01) {
      others += s.seconds;
      continue;
    }
    std::snprintf(buf, sizeof buf, " %.2f s", s.seconds);
    line += (line.empty() ? "" : ", ") + s.name + buf;
  }
  std::snprintf(buf, sizeof buf, "%sothers %.2f s", line.empty() ? "" : ", ", others);
  std::printf("set-up     %.2f s: %s%s\n", total, line.c_str(), buf);
}

// A run with ghost-corrected materials: the stable step measured on its engine, dt = "auto" taken
// from it (measure_ghost_step), both reported. Other runs: none (the families' estimate holds).
std::optional<double> measured_stable_step(Simulation& sim) {
  double dt = sim.setup.dt;
  const std::optional<MeasuredStep> measured =
      measure_ghost_step(*sim.engine, sim.setup.input, sim.scene.dt_auto, sim.setup.critical_dt, dt);
  if (!measured) return std::nullopt;
  sim.stages.push_back({"stable step", measured->seconds});
  sim.setup.dt = dt;
  sim.setup.input.step.dt = real(dt);
  std::printf(
      "stability  with ghosts, measured on the engine: stable step %.4g s (Lanczos, %d force passes, "
      "%.2f s); dt = %.4g s is %.2f of it%s\n",
      measured->stable, measured->passes, measured->seconds, dt, dt / measured->stable,
      sim.scene.dt_auto ? " (dt = \"auto\")" : "");
  return measured->stable;
}

// Makes the engine (the particles' families) and reports it; dt must not exceed the stable time
// step of the families (measured, with ghosts) unless allowed.
void start_engine(Simulation& sim, const RunOptions& opt) {
  const SetupResult& setup = sim.setup;
  const auto t_setup = std::chrono::steady_clock::now();
  if (opt.explicit_families) sim.setup.input.lattice_families = false;
  sim.engine = make_engine(sim.backend, setup.input);
  Engine& engine = *sim.engine;
  std::vector<StageTime> engine_stages;
  for (const SetupStage& s : engine.setup_stages()) engine_stages.push_back({s.name, s.seconds});
  sim.stages.push_back(
      {"engine", std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count()});
  split_last_stage(sim.stages, engine_stages, "engine ", "engine");
  const FamilyStats& fam = engine.family_stats();
  std::printf("device     %s [%s]\n", engine.device_name().c_str(), backend_name(sim.backend));
  std::printf(
      "bonds      %lld (per particle min %d, mean %.1f, max %d); families built in %.2f s; %.1f MiB\n",
      (long long)fam.bonds, fam.min, fam.mean, fam.max,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count(),
      double(engine.memory_bytes()) / (1 << 20));
  // (The bonds a crack and the shards both weaken count once, in the cracks' line when both exist.)
  if (!setup.input.cuts.empty())
    std::printf("cracks     %zu triangles: %lld bonds removed, %lld weakened (per direction%s)\n",
                setup.input.cuts.size(), (long long)fam.cuts.removed, (long long)fam.cuts.weakened,
                setup.shards.cells > 0 ? ", with the shards'" : "");
  if (setup.pattern.bodies > 0)
    std::printf(
        "shards     pattern: %lld broken bonds of the earlier run kept as faces (per bond); its dust, "
        "%lld particles, in %lld cells%s\n",
        (long long)setup.pattern.faces, (long long)setup.pattern.dust, (long long)setup.pattern.cells,
        setup.pattern.dust_materials.empty() ? "" : " of their own hold");
  if (setup.shards.cells > 0)
    std::printf("shards     %lld cells of %lld particles (%.1f per cell); bonds between cells weakened%s\n",
                (long long)setup.shards.cells, (long long)setup.shards.particles,
                double(setup.shards.particles) / double(setup.shards.cells),
                setup.input.cuts.empty()
                    ? (" (" + std::to_string(fam.cuts.weakened) + " per direction)").c_str()
                    : "");
  const double family_dt = engine.critical_time_step();
  if (double dt = setup.dt; auto_step_within_families(engine, sim.scene.dt_auto, family_dt, dt)) {
    sim.setup.dt = dt;
    sim.setup.input.step.dt = real(dt);
    std::printf(
        "time step  dt = \"auto\" takes the families' stable step %.4g s, shorter than half the "
        "continuum estimate\n",
        dt);
  }
  std::printf("stability  dt_c from the families %.4g s (continuum estimate %.4g s): dt = %.2f of it\n",
              family_dt, setup.critical_dt, setup.dt / family_dt);
  const std::optional<double> measured = sim.measured_dt = measured_stable_step(sim);
  const SurfaceGhostCounts ghosts = engine.surface_ghosts();
  if (ghosts.ghosted + ghosts.thin + ghosts.precracked > 0)
    std::printf(
        "ghosts     %lld surface particles complete their families with ghosts (%lld on the linear "
        "fit); %lld without (%lld too thin to fit, %lld at pre-cracks)\n",
        (long long)ghosts.ghosted, (long long)ghosts.linear, (long long)(ghosts.thin + ghosts.precracked),
        (long long)ghosts.thin, (long long)ghosts.precracked);
  check_family_time_step(sim.scene, setup.dt, measured.value_or(family_dt), opt.allow_unstable_dt,
                         measured.has_value());
}

// The run's output folder: --out, else out/<scene name>.
std::string output_folder(const RunOptions& opt) {
  return opt.out.empty() ? "out/" + std::filesystem::path(opt.scene).stem().string() : opt.out;
}

FolderUse folder_use(const RunOptions& opt) {
  return !opt.resume.empty() ? FolderUse::kResume : opt.overwrite ? FolderUse::kOverwrite : FolderUse::kNew;
}

// Takes the output folder (default out/<scene name>) for this run: locked, checked for another
// run's files (replaced with --overwrite) or, for a resume, for the manifest the checkpoint must
// match; then the manifest is written and the folder's journal started.
std::unique_ptr<RunFolder> claim_output_folder(const Simulation& sim, const RunOptions& opt,
                                               const std::optional<RunCheckpoint>& resume) {
  const std::string out = output_folder(opt);
  auto folder = std::make_unique<RunFolder>(out, folder_use(opt));
  if (resume) {
    const RunManifest& m = folder->found();
    if (m.scene_hash != resume->scene_hash || m.scale != resume->scale || m.overrides != resume->overrides)
      throw ResumeError("cannot resume: the checkpoint in '" + out + "' was not written by the run its " +
                        kManifestFileName + " records (that run is of '" + m.scene_path + "' at scale " +
                        format_number(m.scale) + ", the checkpoint of '" + resume->scene_path +
                        "' at scale " + format_number(resume->scale) +
                        "): it was copied from another run's folder");
    check_resume_target(*resume, m, sim.scene.frames, out);
    folder->start(m);
    return folder;
  }
  RunManifest m;
  m.scene_path = std::filesystem::absolute(sim.scene.path).lexically_normal().string();
  m.scene_hash = scene_fingerprint(sim.scene.path, opt.overrides);
  m.scale = opt.scale;
  m.overrides = opt.overrides;
  folder->start(m);
  return folder;
}

// Writes the rest state once into the run's folder.
void write_rest_outputs(const Simulation& sim, const std::string& out) {
  const Scene& scene = sim.scene;
  const SetupResult& setup = sim.setup;
  if (scene.write_binary) write_rest_file(out + "/" + kRestFileName, rest_data(setup.input.particles));
  if (scene.write_binary && !setup.voronoi.empty()) {
    // The Voronoi bodies' trimtopes in rest space, for `perifrac render`.
    RestTrimtopes trimtopes;
    for (const VoronoiBody& v : setup.voronoi)
      append(trimtopes, rest_trimtopes(v.geometry, v.first_particle));
    write_trimtopes_file(out + "/" + kTrimtopesFileName, trimtopes);
  }
  // The tet bodies' tetrahedra in rest space, for `perifrac render`.
  if (scene.write_binary && !setup.embedded.empty())
    write_tets_file(out + "/" + kTetsFileName, setup.embedded);
}

// Where the frame loop starts: the first frame to simulate and the energy the run started with.
struct RunStart {
  int64_t first_frame = 1;
  Energy energy0;
};

// An energy term for a message: "<value> J", or "not finite" (no message prints inf or NaN).
std::string finite_or_not(double joules) {
  return std::isfinite(joules) ? format_number(joules) + " J" : "not finite";
}

// A fresh run: checks the state it starts from (nothing non-finite is ever written), writes frame 0
// and logs the energy it starts with. Throws SceneError when the scene's numbers overflow.
RunStart start_fresh_run(Simulation& sim, RunOutput& output) {
  RunStart start;
  start.energy0 = sim.engine->energy();
  const Energy& e = start.energy0;
  const int64_t bad = sim.engine->first_non_finite();
  if (bad >= 0 || !std::isfinite(e.balance()))
    throw SceneError(sim.scene.path, bad >= 0 ? "bodies" : "materials",
                     bad >= 0
                         ? "particle " + std::to_string(bad) + " of body '" +
                               sim.setup.body_names[size_t(sim.setup.input.particles.body[size_t(bad)])] +
                               "' starts with a state that is not finite: its numbers are out of range"
                         : "the energy at the start is not finite (kinetic " + finite_or_not(e.kinetic) +
                               ", strain " + finite_or_not(e.strain) + ", gravity " +
                               finite_or_not(e.gravity) + "): the scene's numbers are out of range");
  output.write_frame(0, start.energy0);  // (its outputs made while the first frame steps)
  return start;
}

// A resumed run: restores the state after the checkpointed frame (moved from `c`).
RunStart restore_run(Simulation& sim, RunOutput& output, RunCheckpoint& c) {
  sim.engine->restore(c.engine);
  output.restore(c);
  RunStart start;
  start.energy0 = c.energy0;
  start.first_frame = c.frame + 1;
  if (const size_t dropped = output.folder().drop_frames_after(c.frame))
    std::printf("output     removed %zu file(s) written after the checkpoint\n", dropped);
  std::printf("resume     from frame %lld (step %lld) of %s\n", (long long)c.frame, (long long)c.engine.step,
              output.dir().c_str());
  return start;
}

// A run resumed after its last frame: writes the end-of-run outputs and says how to extend it.
int finish_complete_run(RunOutput& output, const RunCheckpoint& c) {
  output.finish_complete_run();
  std::printf("output     the run is complete at frame %lld; pass --frames N (N > %lld) to extend it\n",
              (long long)c.frame, (long long)c.frame);
  return kExitOk;
}

// Writes the whole state after `frame` to OUT/checkpoint.pck, atomically replacing the previous one.
void write_run_checkpoint(const Simulation& sim, const RunOptions& opt, RunOutput& output,
                          const Energy& energy0, int64_t frame) {
  RunCheckpoint c;
  // The scene, by absolute path (resumable from anywhere) and relative to the run's folder (found
  // when both moved together).
  namespace fs = std::filesystem;
  c.scene_path = fs::absolute(sim.scene.path).lexically_normal().string();
  c.scene_relative =
      fs::path(c.scene_path).lexically_relative(fs::absolute(output.dir()).lexically_normal()).string();
  c.overrides = opt.overrides;
  c.scene_hash = scene_fingerprint(sim.scene.path, opt.overrides);
  c.setup_hash = setup_fingerprint(sim.setup.input);
  c.scale = opt.scale;
  c.steps_per_frame = sim.scene.steps_per_frame;
  c.frames = sim.scene.frames;
  c.blend_frames = opt.blend_frames;
  c.allow_unstable_dt = opt.allow_unstable_dt;
  c.explicit_families = opt.explicit_families;
  c.checkpoint_every = opt.checkpoint_every;
  c.checkpoint_minutes = opt.checkpoint_minutes;
  c.backend = backend_name(sim.backend);
  c.frame = frame;
  sim.engine->save(c.engine);
  c.energy0 = energy0;
  output.save(c);
  write_checkpoint(output.dir() + "/" + kCheckpointFileName, c);
}

// A particle no longer finite after the steps of `frame`: reports the blow-up with the step and the
// frames written, and returns true.
bool stopped_by_non_finite(const Simulation& sim, int64_t frame, const std::string& out) {
  Engine& engine = *sim.engine;
  const int64_t bad = engine.first_non_finite();
  if (bad < 0) return false;
  std::fprintf(
      stderr,
      "\nerror: numerical blow-up: particle %lld is not finite by step %lld (frame %lld, between steps "
      "%lld and %lld); dt = %.3g s is %.2f of the critical time step. Frames up to %lld are written "
      "in %s\n",
      (long long)bad, (long long)engine.step(), (long long)frame,
      (long long)(engine.step() - sim.scene.steps_per_frame), (long long)engine.step(), sim.setup.dt,
      sim.setup.dt / sim.setup.critical_dt, (long long)(frame - 1), out.c_str());
  return true;
}

// The energy grown past `limit` times the energy in play by `frame` (the watchdog's `excess`), or
// not finite: reports the blow-up in finite numbers with the fastest particle and the frames
// written, and returns true.
bool stopped_by_energy_growth(const Simulation& sim, const Energy& energy0, const Energy& energy,
                              double excess, double limit, int64_t frame, const std::string& out) {
  const bool finite = std::isfinite(energy.balance()) && std::isfinite(excess);
  if (finite && !(excess > limit)) return false;
  Engine& engine = *sim.engine;
  char growth[160];
  if (finite)
    std::snprintf(growth, sizeof growth, "the energy grew by %.3g J (%.2f times the energy in play%s)",
                  energy.balance() - energy0.balance(), excess,
                  limit < 1 ? "; past the stable time step a run stops at 0.1" : "");
  else
    std::snprintf(growth, sizeof growth, "the energy is no longer finite (it was %.3g J at the start)",
                  energy0.balance());
  // The likely cause: particles that started in a collider (warned at set-up), else the step.
  char cause[160] = "";
  if (sim.setup.started_in_colliders > 0)
    std::snprintf(cause, sizeof cause,
                  "; %lld particles started inside or pressed into colliders (warned at set-up): move them "
                  "clear",
                  (long long)sim.setup.started_in_colliders);
  else if (sim.scene.contact)
    std::snprintf(cause, sizeof cause, "; a high contact stiffness needs a smaller dt too");
  std::fprintf(stderr,
               "\nerror: numerical blow-up: %s by step %lld (frame %lld); particle %lld moves fastest. dt = "
               "%.3g s is %.2f of the critical time step%s. Frames up to %lld are written in %s\n",
               growth, (long long)engine.step(), (long long)frame, (long long)fastest_particle(engine),
               sim.setup.dt, sim.setup.dt / sim.setup.critical_dt, cause, (long long)(frame - 1),
               out.c_str());
  return true;
}

// The watchdog's limit on the energy balance's growth, as a fraction of the energy in play: a
// blow-up (1) for a run within the stable time step, whose drift stays a few percent (bench/accuracy/
// stability.md: at most 6% over the stress scenes); 0.1, the stress test's own bound of a stable
// run, for one past it under --allow-unstable-dt, which has no error bound of its own.
double energy_growth_limit(const Simulation& sim, const RunOptions& opt) {
  const double stable = sim.measured_dt.value_or(sim.engine->critical_time_step());
  const bool past_stable = sim.setup.dt > std::fmin(sim.setup.critical_dt, stable);
  return opt.allow_unstable_dt && past_stable ? 0.1 : 1.0;
}

// Whether a checkpoint is due after `frame`: every N frames, every M minutes of wall time since
// the last one, and on SIGINT/SIGTERM.
bool checkpoint_due(const RunOptions& opt, int64_t frame, double seconds_since_last) {
  const bool by_count = opt.checkpoint_every > 0 && frame % opt.checkpoint_every == 0;
  const bool by_time = opt.checkpoint_minutes > 0 && seconds_since_last >= 60 * opt.checkpoint_minutes;
  return by_count || by_time || InterruptGuard::signal_received();
}

// What the progress line after a frame says of the engine, taken when the frame is written.
struct Progress {
  int64_t frame = 0, frames = 0, step = 0;
  double steps_per_s = 0, eta = 0, broken = 0, excess = 0;
};

// `first_step`: the engine's step when the frame loop began (a resumed run's may lie inside a frame).
Progress progress_after(const Simulation& sim, int64_t frame, int64_t first_step, double elapsed,
                        double excess) {
  const Scene& scene = sim.scene;
  Engine& engine = *sim.engine;
  Progress p;
  const int64_t done = std::max<int64_t>(engine.step() - first_step, 1);
  p.frame = frame;
  p.frames = scene.frames;
  p.step = engine.step();
  p.steps_per_s = double(done) / elapsed;
  p.eta = elapsed / double(done) * double(scene.frames * scene.steps_per_frame - p.step);
  const int64_t bonds = engine.family_stats().bonds;
  p.broken = bonds > 0 ? double(engine.broken_bonds()) / double(bonds) : 0;
  p.excess = excess;
  return p;
}

// The progress line: speed, time left, broken bonds, energy balance and fragments (rewritten in
// place on a terminal).
void print_progress(const Progress& p, const std::string& fragment_log, bool tty) {
  std::printf(
      "%sframe %lld/%lld  step %lld  %.0f steps/s  ETA %s  broken %.3f%%  energy balance %+.2f%%  %s%s",
      tty ? "\r" : "", (long long)p.frame, (long long)p.frames, (long long)p.step, p.steps_per_s,
      format_duration(p.eta).c_str(), 100 * p.broken, 100 * p.excess, fragment_log.c_str(),
      tty ? "   " : "\n");
  std::fflush(stdout);
}

// Advances the engine to `target_step` in chunks of about a fifth of a second, so that SIGINT or
// SIGTERM stops a run within a second even when a frame takes hours. (Chunks change no bit: the
// engine's steps do not depend on how they are grouped.) False when a signal came first.
class StepPacer {
 public:
  bool advance_to(Engine& engine, int64_t target_step) {
    while (engine.step() < target_step) {
      if (InterruptGuard::signal_received()) return false;
      const int64_t steps = std::min(chunk_, target_step - engine.step());
      const auto t0 = std::chrono::steady_clock::now();
      engine.advance(steps);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      chunk_ =
          std::clamp(int64_t(0.2 * double(steps) / std::max(seconds, 1e-9)), int64_t(1), kMaxStepsPerFrame);
    }
    return true;
  }

 private:
  int64_t chunk_ = 1;
};

// Where the frame loop's wall time goes, printed at the end of a run: what is not stepping is
// what the output costs the run (issue 27: at most 15% of the stepping).
// Where the command's wall time went outside the frame loop.
struct RunTimes {
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  double engine = 0;   // the scene read, its particles made, the engine set up
  double outputs = 0;  // the output folder claimed, the rest outputs, frame 0 (or the restore)
};

struct LoopTimes {
  double total = 0;   // the whole loop
  double steps = 0;   // advancing the engine (kernels, and the host work between them)
  double drain = 0;   // waiting for the output threads: for room in their queue, then for the last frames
  double last = 0;    //   of it, the last frames' (the queue drained at the end of the loop)
  double checks = 0;  // the blow-up checks and the energy
  double read = 0;    // the frames taken: their read-back started (write_frame's own part)
  double checkpoints = 0;
};

// The frame loop: simulates and writes the frames from start.first_frame on, with checkpoints and a
// progress line. Returns kExitOk, or kExitBlowUp / kExitInterrupted when it stopped early.
int run_frames(Simulation& sim, const RunOptions& opt, RunOutput& output, const RunStart& start,
               LoopTimes& times) {
  Engine& engine = *sim.engine;
  const Scene& scene = sim.scene;
  auto last_checkpoint = std::chrono::steady_clock::now();
  const bool tty = isatty(fileno(stdout));
  const auto t0 = std::chrono::steady_clock::now();
  StepPacer pacer;
  const int64_t first_step = engine.step();
  const double growth_limit = energy_growth_limit(sim, opt);
  for (int64_t frame = start.first_frame; frame <= scene.frames; ++frame) {
    auto t = std::chrono::steady_clock::now();
    // (A checkpoint written mid-frame resumes inside the frame: frame f ends at step f * steps.)
    if (!pacer.advance_to(engine, frame * scene.steps_per_frame)) {
      write_run_checkpoint(sim, opt, output, start.energy0, frame - 1);
      std::printf(
          "%sinterrupted in frame %lld at step %lld: checkpoint written; continue with: perifrac run "
          "--resume "
          "%s\n",
          tty ? "\n" : "", (long long)frame, (long long)engine.step(), output.dir().c_str());
      return kExitInterrupted;
    }
    t = lap(t, times.steps);
    output.wait_for_room();  // (the output threads may still be making the frames before)
    t = lap(t, times.drain);
    if (stopped_by_non_finite(sim, frame, output.dir())) return kExitBlowUp;
    const Energy energy = engine.energy();
    const double excess = energy_excess(start.energy0, energy);
    if (stopped_by_energy_growth(sim, start.energy0, energy, excess, growth_limit, frame, output.dir()))
      return kExitBlowUp;
    const auto now = std::chrono::steady_clock::now();
    t = lap(t, times.checks);
    const Progress progress =
        progress_after(sim, frame, first_step, std::chrono::duration<double>(now - t0).count(), excess);
    output.write_frame(frame, energy, [progress, tty](const std::string& fragments) {
      print_progress(progress, fragments, tty);
    });
    t = lap(t, times.read);

    if (checkpoint_due(opt, frame, std::chrono::duration<double>(now - last_checkpoint).count())) {
      write_run_checkpoint(sim, opt, output, start.energy0, frame);
      last_checkpoint = now;
      lap(t, times.checkpoints);
    }
    if (InterruptGuard::signal_received()) {
      output.drain();
      std::printf(
          "%sinterrupted after frame %lld: checkpoint written; continue with: perifrac run --resume %s\n",
          tty ? "\n" : "", (long long)frame, output.dir().c_str());
      return kExitInterrupted;
    }
  }
  const auto t = std::chrono::steady_clock::now();
  output.drain();
  lap(t, times.last);
  times.drain += times.last;
  times.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (tty) std::printf("\n");
  return kExitOk;
}

// "R times the stepping", or "no steps" for a run of frame 0 alone.
std::string times_the_stepping(double seconds, double stepping) {
  if (!(stepping > 0)) return "no steps";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f times the stepping", seconds / stepping);
  return buf;
}

// The end of a run: the kernel table, the end-of-run outputs and where they are.
void finish_run(const Simulation& sim, RunOutput& output, int64_t first_frame, const LoopTimes& times,
                const RunTimes& run) {
  const Scene& scene = sim.scene;
  std::printf(
      "frame loop %.2f s (%s): stepping %.2f s, waiting for the output thread %.2f s (the last frames "
      "%.2f s), frames taken %.2f s, checks and energy %.2f s, checkpoints %.2f s\n",
      times.total, times_the_stepping(times.total, times.steps).c_str(), times.steps, times.drain, times.last,
      times.read, times.checks, times.checkpoints);
  const int64_t steps = (scene.frames - first_frame + 1) * scene.steps_per_frame;
  std::printf("kernels (%lld steps, %s):\n", (long long)steps, backend_name(sim.backend));
  print_kernel_table(std::cout, kernel_rows(sim.engine->stats(), "pd/", sim.engine->family_stats().bonds,
                                            steps, sim.engine->graphed_steps()));
  const auto end = std::chrono::steady_clock::now();
  output.finish();
  double end_outputs = 0;
  const double wall = std::chrono::duration<double>(lap(end, end_outputs) - run.started).count();
  const RunOutput::Times& out = output.times();
  const FragmentOutput::AnalysisTimes& found = output.analysis_times();
  std::printf(
      "output threads over %lld frames: fragment outputs set up %.2f s, frames read back %.2f s, fragments "
      "found %.2f s (components %.2f, fits %.2f, crack mesh %.2f, blending %.2f, statistics %.2f s) and "
      "crack "
      "surfaces taken %.2f s on the first (longest frame %.3f s), the frames written %.2f s on the second "
      "(longest %.3f s; the fragment files %.2f s beside the frame files %.2f s)\n",
      (long long)out.frames, out.setup, out.read_back, out.analysis, found.components, found.fits,
      found.crack_mesh, found.blending, found.statistics, out.crack_surfaces, out.longest_analysis,
      out.writing, out.longest_writing, out.fragment_files, out.frame_files);
  std::printf("output     %s (%lld frames; %zu fragment pieces in fragments.obj)\n", output.dir().c_str(),
              (long long)scene.frames + 1, output.fragment_pieces());
  std::printf(
      "run        %.2f s (%s): set-up %.2f s (scene and engine %.2f s, outputs to frame "
      "%lld "
      "%.2f s), frame loop %.2f s, end-of-run outputs %.2f s\n",
      wall, times_the_stepping(wall, times.steps).c_str(), run.engine + run.outputs, run.engine,
      (long long)first_frame - 1, run.outputs, times.total, end_outputs);
}

}  // namespace

namespace {

// `setting_up`: true until the set-up's last stage (the engine started), for run_command to tell an
// interrupted set-up from a failure after it.
int run_guarded(const RunOptions& options, std::optional<InterruptGuard>& interrupt, bool& setting_up) {
  RunTimes run;
  RunOptions opt = options;
  output_thread_wanted();  // a bad PERIFRAC_OUTPUT_THREAD is refused before the set-up's work
  std::optional<RunCheckpoint> resume;
  if (!opt.resume.empty()) resume = open_resume(opt);
  // A folder this run may not use is refused before the set-up's work (and again under its lock).
  if (const auto found = check_run_folder(output_folder(opt), folder_use(opt)); resume && found)
    check_resume_target(*resume, *found, opt.frames, opt.out);
  Simulation sim = set_up_simulation(opt, resume);
  start_engine(sim, opt);
  throw_if_interrupted("set-up");  // (the engine's families and stable step are a stage of their own)
  setting_up = false;
  auto t = lap(run.started, run.engine);
  StageClock clock(&sim.stages, false);  // (an interrupt from here on stops in the frame loop)
  // Only rank 0 of a run over MPI ranks gets here (the others serve its engine).
  const std::unique_ptr<RunFolder> folder = claim_output_folder(sim, opt, resume);
  clock.lap("output folder");
  write_rest_outputs(sim, folder->dir());
  clock.lap("rest files");
  RunOutput output(sim.scene, sim.setup, *sim.engine, sim.backend, opt.blend_frames, *folder);
  clock.lap("output set-up");

  // A fresh run writes frame 0; a resumed one restores the state after its checkpointed frame.
  const RunStart start = resume ? restore_run(sim, output, *resume) : start_fresh_run(sim, output);
  // Killed after its last checkpoint: finish the end-of-run outputs; nothing else to run.
  if (resume && start.first_frame > sim.scene.frames) return finish_complete_run(output, *resume);
  sim.engine->stats().reset_times();
  lap(t, run.outputs);
  clock.lap(resume ? "restore" : "frame 0");
  print_setup_stages(sim.stages);

  // From here on, SIGINT/SIGTERM ends the run inside or after a frame with a checkpoint (over MPI
  // ranks, from here on only: the ranks' set-ups must not part ways).
  if (!interrupt) interrupt.emplace();
  LoopTimes times;
  if (const int code = run_frames(sim, opt, output, start, times); code != kExitOk) return code;
  finish_run(sim, output, start.first_frame, times, run);
  // Interrupted after the last step, while the last frames' outputs were written: they are
  // complete, but for images a live render left unfinished.
  if (InterruptGuard::signal_received()) {
    std::printf(
        "interrupted after the last frame: every frame's files are written; images a [render] block "
        "left unfinished: perifrac render %s\n",
        output.dir().c_str());
    return kExitInterrupted;
  }
  return kExitOk;
}

}  // namespace

int run_command(const RunOptions& options) {
  // One process: SIGINT/SIGTERM during the set-up stop it between two stages (an external TetGen
  // killed), with no file half-written; the folder, if claimed, holds a run that ended before its
  // first frame, which the next run takes over.
  std::optional<InterruptGuard> interrupt;
  if (!world_comm()) interrupt.emplace();
  bool setting_up = true;
  try {
    return run_guarded(options, interrupt, setting_up);
  } catch (const std::exception& e) {
    // An interrupt's stop, or a set-up failure it caused (TetGen killed by the terminal's Ctrl-C);
    // a failure after the set-up is reported as it is.
    const bool stopped = dynamic_cast<const Interrupted*>(&e) != nullptr;
    if (!stopped && !(setting_up && InterruptGuard::signal_received())) throw;
    std::printf("\n%s: no frame written; start the run again to run it\n",
                stopped ? e.what() : "interrupted during set-up");
    return kExitInterrupted;
  }
}

}  // namespace pd
