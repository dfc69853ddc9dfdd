#include "host/app/run.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "cuda/engine/engine.h"
#include "host/app/backend_choice.h"
#include "host/app/checkpoint.h"
#include "host/app/energy_watch.h"
#include "host/app/interrupt.h"
#include "host/app/kernel_report.h"
#include "host/app/live_render.h"
#include "host/fragments/fragment_output.h"
#include "host/fragments/tet_file.h"
#include "host/fragments/trimtope_file.h"
#include "host/io/atomic_file.h"
#include "host/io/frame_file.h"
#include "host/io/vtk_writer.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

namespace {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
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

// A dt above the stable limit is a user mistake unless explicitly allowed.
void check_time_step(const Scene& scene, const SetupResult& setup, bool allow) {
  if (setup.dt <= setup.critical_dt || allow) return;
  std::ostringstream msg;
  msg << "dt = " << setup.dt << " s exceeds the stable time step " << setup.critical_dt
      << " s of the stiffest material (allowed: dt <= " << setup.critical_dt
      << "; pass --allow-unstable-dt to run anyway)";
  throw SceneError(scene.path, "simulation.dt", msg.str());
}

RestData rest_data(const ParticleSet& ps) {
  RestData r;
  r.position = ps.rest;
  r.volume.assign(ps.volume.begin(), ps.volume.end());
  r.body = ps.body;
  r.material.assign(ps.material.begin(), ps.material.end());
  return r;
}

// Gathers one frame's per-particle data from the engine.
FrameData frame_data(Engine& engine, const ParticleSet& ps, const std::vector<int32_t>& count,
                     int64_t frame) {
  ParticleState s;
  engine.read_state(s);
  FrameData f;
  f.frame = frame;
  f.step = engine.step();
  f.time = engine.time();
  f.position.resize(ps.size());
  f.damage.resize(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    f.position[i] = ps.rest[i] + s.disp[i];
    f.damage[i] = count[i] > 0 ? 1.0f - float(s.intact[i]) / float(count[i]) : 0.0f;
  }
  f.velocity = std::move(s.vel);
  f.body = ps.body;
  return f;
}

// Reads the checkpoint of `opt.resume` and takes over what the run was started with: the scene
// (unless given again), backend (unless given), scale, steps per frame, blending, and the frame
// count unless --frames extends it.
RunCheckpoint open_resume(RunOptions& opt) {
  const std::string path = opt.resume + "/" + kCheckpointFileName;
  if (!std::filesystem::exists(path))
    throw ResumeError("cannot resume from '" + opt.resume + "': it holds no " + kCheckpointFileName +
                      " (the run wrote none yet, or this is not a run's output folder); start the run "
                      "again without --resume");
  RunCheckpoint c;
  try {
    c = read_checkpoint(path);
  } catch (const IoError& e) {
    throw ResumeError(std::string(e.what()) + "; start the run again without --resume");
  }
  if (opt.scene.empty()) opt.scene = c.scene_path;
  if (opt.overrides.empty()) opt.overrides = c.overrides;
  if (!opt.out.empty() && opt.out != opt.resume)
    throw ResumeError("--out '" + opt.out + "' and --resume '" + opt.resume +
                      "' differ: a resumed run continues in its own folder");
  opt.out = opt.resume;
  if (opt.backend == "auto") opt.backend = c.backend;  // bit for bit needs the same backend
  opt.scale = c.scale;
  opt.blend_frames = c.blend_frames;
  opt.allow_unstable_dt = opt.allow_unstable_dt || c.allow_unstable_dt;
  if (opt.steps_per_frame >= 1 && opt.steps_per_frame != c.steps_per_frame)
    throw ResumeError("--steps-per-frame " + std::to_string(opt.steps_per_frame) + " differs from the " +
                      std::to_string(c.steps_per_frame) + " of the checkpointed run");
  opt.steps_per_frame = c.steps_per_frame;
  if (opt.frames < 0) opt.frames = c.frames;
  return c;
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

}  // namespace

int run_command(const RunOptions& options) {
  RunOptions opt = options;
  std::optional<RunCheckpoint> resume;
  if (!opt.resume.empty()) resume = open_resume(opt);
  Scene scene = load_scene(opt.scene, opt.overrides);
  if (opt.frames >= 0) scene.frames = opt.frames;
  if (opt.steps_per_frame >= 1) scene.steps_per_frame = opt.steps_per_frame;
  std::string note;
  const Backend backend = choose_backend(opt.backend, &note);
  const SetupResult setup = setup_scene(scene, setup_options_for(scene, opt.scale, backend));
  print_setup(scene, setup, opt);
  check_time_step(scene, setup, opt.allow_unstable_dt);
  if (!note.empty()) std::printf("backend    %s\n", note.c_str());
  if (resume) check_resume(*resume, scene, opt.overrides, setup, backend);
  const auto t_setup = std::chrono::steady_clock::now();
  std::unique_ptr<Engine> engine = make_engine(backend, setup.input);
  const FamilyStats& fam = engine->family_stats();
  std::printf("device     %s [%s]\n", engine->device_name().c_str(), backend_name(backend));
  std::printf(
      "bonds      %lld (per particle min %d, mean %.1f, max %d); families built in %.2f s; %.1f MiB\n",
      (long long)fam.bonds, fam.min, fam.mean, fam.max,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count(),
      double(engine->memory_bytes()) / (1 << 20));
  if (!setup.input.cuts.empty())
    std::printf("cracks     %zu triangles: %lld bonds removed, %lld weakened (per direction)\n",
                setup.input.cuts.size(), (long long)fam.cuts.removed, (long long)fam.cuts.weakened);
  const double family_dt = engine->critical_time_step();
  std::printf("stability  dt_c from the families %.4g s (continuum estimate %.4g s): dt = %.2f of it\n",
              family_dt, setup.critical_dt, setup.dt / family_dt);
  if (setup.dt > family_dt && !opt.allow_unstable_dt) {
    std::ostringstream msg;
    msg << "dt = " << setup.dt << " s exceeds the stable time step " << family_dt
        << " s computed from the particles' families (allowed: dt <= " << family_dt
        << "; pass --allow-unstable-dt to run anyway)";
    throw SceneError(scene.path, "simulation.dt", msg.str());
  }

  // Output folder: rest state once, then one set of files per frame.
  const std::string out =
      opt.out.empty() ? "out/" + std::filesystem::path(scene.path).stem().string() : opt.out;
  ensure_directory(out);
  if (const size_t stale = remove_stale_temporaries(out))
    std::printf("output     removed %zu partial file(s) of an interrupted run\n", stale);
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
  // [render]: frames rendered as the run writes them.
  std::unique_ptr<LiveRender> live;
  if (scene.render) live = std::make_unique<LiveRender>(scene, out, backend_name(backend));
  PvdSeries series(out, "particles");
  BondLists bonds;
  engine->read_bonds(bonds);
  const std::vector<int32_t>& count = bonds.count;
  std::vector<VoronoiElements> voronoi_elements;
  for (const VoronoiBody& v : setup.voronoi) voronoi_elements.push_back({v.first_particle, &v.geometry});
  FragmentOutput fragments(setup.input, bonds, {out, opt.blend_frames}, setup.adjacency, setup.embedded,
                           voronoi_elements);
  if (const FaceLinks& links = fragments.face_links(); links.indirect() + links.unlinked() > 0)
    std::printf(
        "elements   %zu touching pairs farther apart than the horizon: %zu hold through common "
        "neighbours, %zu have no bond path (cracks from the start)\n",
        links.indirect() + links.unlinked(), links.indirect(), links.unlinked());
  std::string fragment_log;
  auto write_frame = [&](int64_t frame) {
    FrameData f = frame_data(*engine, setup.input.particles, count, frame);
    if (frame > 0) engine->read_bonds(bonds);
    fragment_log = format_component_stats(fragments.process(f, bonds));
    if (scene.write_binary) write_frame_file(out + "/" + frame_file_name(frame, "pfr"), f);
    if (scene.write_vtk) {
      const std::string name = frame_file_name(frame, "vtu");
      write_vtu(out + "/" + name, f);
      series.add(f.time, name);
    }
    if (live) live->frame(frame);
  };

  // A fresh run writes frame 0; a resumed one restores the state after its checkpointed frame.
  EnergyLog energy_log(out + "/energy.csv");
  Energy energy0;
  int64_t first_frame = 1;
  if (resume) {
    engine->restore(resume->engine);
    fragments.smoother().restore(std::move(resume->smoother));
    series.restore(std::move(resume->series));
    energy_log.restore(std::move(resume->energy_log));
    energy0 = resume->energy0;
    first_frame = resume->frame + 1;
    std::printf("resume     from frame %lld (step %lld) of %s\n", (long long)resume->frame,
                (long long)resume->engine.step, out.c_str());
    if (first_frame > scene.frames) {
      // Killed after its last checkpoint: finish the end-of-run outputs; nothing else to run.
      engine->read_bonds(bonds);
      fragments.find_components(bonds);
      fragments.write_meshes();
      std::printf("output     the run is complete at frame %lld; pass --frames N (N > %lld) to extend it\n",
                  (long long)resume->frame, (long long)resume->frame);
      return kExitOk;
    }
  } else {
    write_frame(0);
    energy0 = engine->energy();
    energy_log.add(0, 0, 0.0, energy0);
  }
  engine->stats().reset_times();

  // Checkpoints: the whole state after a frame, atomically replacing the previous one.
  const std::string scene_hash_path = scene.path;
  auto write_checkpoint_now = [&](int64_t frame) {
    RunCheckpoint c;
    c.scene_path = scene.path;
    c.overrides = opt.overrides;
    c.scene_hash = scene_fingerprint(scene_hash_path, opt.overrides);
    c.setup_hash = setup_fingerprint(setup.input);
    c.scale = opt.scale;
    c.steps_per_frame = scene.steps_per_frame;
    c.frames = scene.frames;
    c.blend_frames = opt.blend_frames;
    c.allow_unstable_dt = opt.allow_unstable_dt;
    c.backend = backend_name(backend);
    c.frame = frame;
    engine->save(c.engine);
    c.energy0 = energy0;
    c.energy_log = energy_log.text();
    c.series = series.entries();
    c.smoother = fragments.smoother().history();
    write_checkpoint(out + "/" + kCheckpointFileName, c);
  };
  const InterruptGuard interrupt;
  auto last_checkpoint = std::chrono::steady_clock::now();

  // Frame loop with a progress line; a non-finite state stops the run with the step.
  const bool tty = isatty(fileno(stdout));
  const auto t0 = std::chrono::steady_clock::now();
  for (int64_t frame = first_frame; frame <= scene.frames; ++frame) {
    engine->advance(scene.steps_per_frame);
    const int64_t bad = engine->first_non_finite();
    if (bad >= 0) {
      std::fprintf(
          stderr,
          "\nerror: numerical blow-up: particle %lld is not finite by step %lld (frame %lld, between steps "
          "%lld and %lld); dt = %.3g s is %.2f of the critical time step. Frames up to %lld are written "
          "in %s\n",
          (long long)bad, (long long)engine->step(), (long long)frame,
          (long long)(engine->step() - scene.steps_per_frame), (long long)engine->step(), setup.dt,
          setup.dt / setup.critical_dt, (long long)(frame - 1), out.c_str());
      return kExitBlowUp;
    }
    const Energy energy = engine->energy();
    const double excess = energy_excess(energy0, energy);
    if (excess > 1.0 || !std::isfinite(energy.balance())) {
      std::fprintf(stderr,
                   "\nerror: numerical blow-up: the energy grew by %.3g J (%.1f times the energy in play) by "
                   "step %lld "
                   "(frame %lld); particle %lld moves fastest. dt = %.3g s is %.2f of the critical time "
                   "step%s. Frames "
                   "up to %lld are written in %s\n",
                   energy.balance() - energy0.balance(), excess, (long long)engine->step(), (long long)frame,
                   (long long)fastest_particle(*engine), setup.dt, setup.dt / setup.critical_dt,
                   scene.contact ? "; a high contact stiffness needs a smaller dt too" : "",
                   (long long)(frame - 1), out.c_str());
      return kExitBlowUp;
    }
    energy_log.add(frame, engine->step(), engine->time(), energy);
    write_frame(frame);

    const auto now = std::chrono::steady_clock::now();
    const bool by_count = opt.checkpoint_every > 0 && frame % opt.checkpoint_every == 0;
    const bool by_time =
        opt.checkpoint_minutes > 0 &&
        std::chrono::duration<double>(now - last_checkpoint).count() >= 60 * opt.checkpoint_minutes;
    if (by_count || by_time || InterruptGuard::signal_received()) {
      write_checkpoint_now(frame);
      last_checkpoint = now;
    }
    if (InterruptGuard::signal_received()) {
      std::printf(
          "%sinterrupted after frame %lld: checkpoint written; continue with: perifrac run --resume %s\n",
          tty ? "\n" : "", (long long)frame, out.c_str());
      return kExitInterrupted;
    }

    const double elapsed = std::chrono::duration<double>(now - t0).count();
    const int64_t done = frame - first_frame + 1;
    const double steps_per_s = double(done * scene.steps_per_frame) / elapsed;
    const double eta = elapsed / double(done) * double(scene.frames - frame);
    const double broken = fam.bonds > 0 ? double(engine->broken_bonds()) / double(fam.bonds) : 0;
    std::printf(
        "%sframe %lld/%lld  step %lld  %.0f steps/s  ETA %s  broken %.3f%%  energy balance %+.2f%%  %s%s",
        tty ? "\r" : "", (long long)frame, (long long)scene.frames, (long long)engine->step(), steps_per_s,
        format_duration(eta).c_str(), 100 * broken, 100 * excess, fragment_log.c_str(), tty ? "   " : "\n");
    std::fflush(stdout);
  }
  if (tty) std::printf("\n");

  const int64_t steps = (scene.frames - first_frame + 1) * scene.steps_per_frame;
  std::printf("kernels (%lld steps, %s):\n", (long long)steps, backend_name(backend));
  print_kernel_table(std::cout, kernel_rows(engine->stats(), "pd/", fam.bonds, steps));
  if (live) live->finish();
  fragments.write_meshes();
  std::printf("output     %s (%lld frames; %zu fragment pieces in fragments.obj)\n", out.c_str(),
              (long long)scene.frames + 1, fragments.components().count());
  return kExitOk;
}

}  // namespace pd
