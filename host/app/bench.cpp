#include "host/app/bench.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "cuda/engine/engine.h"
#include "cuda/engine/material.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/engine/step_graphs.h"
#include "cuda/kernel_stats.h"
#include "host/app/backend_choice.h"
#include "host/app/kernel_report.h"
#include "host/app/provenance.h"
#include "host/app/run.h"
#include "host/app/shards_pattern.h"
#include "host/app/time_step_check.h"
#include "host/io/atomic_file.h"
#include "host/io/json_text.h"
#include "host/scene/scene_setup.h"

namespace pd {

namespace {
// What each rank of a partitioned run did between two readings of its counters.
std::vector<RankStats> rank_deltas(const std::vector<RankStats>& before, std::vector<RankStats> after) {
  for (size_t r = 0; r < after.size() && r < before.size(); ++r) {
    after[r].step_seconds -= before[r].step_seconds;
    after[r].halo_seconds -= before[r].halo_seconds;
    after[r].halo_bytes -= before[r].halo_bytes;
    after[r].halo_exchanges -= before[r].halo_exchanges;
  }
  return after;
}

// A glass-like cube of n^3 simple-cubic particles, 1 mm apart, that stays elastic under
// random velocities of 1e-3 m/s (so the break test runs but no bond breaks). The plastic
// variant yields at a stress low enough that the return mapping is exercised.
SimulationInput lattice_input(const BenchOptions& opt) {
  SimulationInput in;
  const double lambda = 1e-3, delta = opt.horizon * lambda;
  in.materials.count = 1;
  Material& m = in.materials.m[0];
  m.horizon = real(delta);
  m.spacing = real(lambda);
  m.contact_spacing = real(lambda);
  m.compression_alpha = real(0.25);
  if (opt.model == "bond_based") {
    m.partial_volumes = 0;
    m.micromodulus = real(pmb_micromodulus(32.81e9, delta));
  } else if (opt.model == "state_based" || opt.model == "plastic" || opt.model == "anisotropic") {
    m.model = kStateBased;
    m.bulk_modulus = real(72e9 / (3 * (1 - 2 * 0.22)));
    m.shear_modulus = real(72e9 / (2 * 1.22));
    if (opt.model == "anisotropic") {  // bonds along z weighted twice: G = I - 0.5 z z^T
      m.anisotropic = 1;
      m.aniso[8] = real(0.5);
    }
    if (opt.model == "plastic") {
      m.plastic = 1;
      m.yield_psi0 = real(yield_psi0(1e3, delta));
      m.plastic_limit = real(0.05);
    }
  } else {
    throw std::invalid_argument(
        "bench: --model must be bond_based, state_based, plastic or anisotropic, got '" + opt.model + "'");
  }
  const int64_t n = opt.lattice;
  in.particles.reserve(size_t(n * n * n));
  uint64_t state = 1;
  auto jiggle = [&]() {  // small deterministic velocities so the state is not trivial
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return real((double(state >> 11) * 0x1p-53 - 0.5) * 2e-3);
  };
  const double vol = lambda * lambda * lambda;
  for (int64_t k = 0; k < n; ++k)
    for (int64_t j = 0; j < n; ++j)
      for (int64_t i = 0; i < n; ++i)
        in.particles.add({real(i * lambda), real(j * lambda), real(k * lambda)},
                         {jiggle(), jiggle(), jiggle()}, real(vol), real(2440 * vol), real(5e-4), 0, 0);
  in.step.dt = real(0x1p-23);
  in.step.contact_stiffness = real(1e8);
  in.contact = opt.contact;
  return in;
}

// "name": seconds, ... of the engine's set-up stages.
std::string stage_json(const std::vector<SetupStage>& stages) {
  std::ostringstream js;
  for (size_t k = 0; k < stages.size(); ++k)
    js << (k ? ", " : "") << "\"" << json_escape(stages[k].name) << "\": " << stages[k].seconds;
  return js.str();
}

}  // namespace

int bench_command(const BenchOptions& opt) {
  if (opt.steps < 1 || opt.warmup < 0 || opt.lattice < 4 || opt.horizon < 1)
    throw std::invalid_argument("bench: need --steps >= 1, --warmup >= 0, --lattice >= 4, --horizon >= 1");
  std::string note;
  const Backend backend = choose_backend(opt.backend, &note);
  std::string workload;
  SimulationInput input;
  const auto setup_start = std::chrono::steady_clock::now();
  Scene scene;
  double critical_dt = INFINITY;  // a scene's continuum estimate
  if (!opt.scene.empty()) {
    scene = load_scene(opt.scene, opt.overrides);
    const SetupResult setup = setup_scene_with_patterns(scene, opt.scale, backend);
    // A scene scaled past its time step would time a blow-up: refused as `perifrac run` does.
    check_time_step(scene, setup, opt.allow_unstable_dt);
    input = setup.input;
    critical_dt = setup.critical_dt;
    workload = std::filesystem::path(opt.scene).stem().string();
  } else {
    if (!opt.overrides.empty()) throw std::invalid_argument("bench: --set needs --scene");
    // The lattice's particles against what the backend holds, before anything is allocated.
    const ParticleBudget budget =
        particle_budget(backend, opt.horizon, opt.model == "plastic", opt.model == "bond_based");
    const double particles = double(opt.lattice) * double(opt.lattice) * double(opt.lattice);
    if (particles > double(budget.max_particles))
      throw ResourceError("bench: --lattice " + std::to_string(opt.lattice) + " is " +
                          std::to_string(int64_t(particles)) + " particles, more than the " +
                          std::to_string(budget.max_particles) + " that fit (" + budget.why +
                          "; allowed: --lattice " +
                          std::to_string(int64_t(std::cbrt(double(budget.max_particles)))) + " or less)");
    input = lattice_input(opt);
    workload = "lattice" + std::to_string(opt.lattice) + "_h" + std::to_string(int(opt.horizon)) + "_" +
               opt.model + (opt.contact ? "_contact" : "");
  }
  if (opt.explicit_families) {
    input.lattice_families = false;
    workload += "_explicit";
  }
  if (opt.screen != "auto") {
    input.screen = opt.screen == "off" ? BondScreen::kOff : BondScreen::kAlways;
    workload += "_screen_" + opt.screen;
  }
  if (opt.contact_rebuild == "full") {
    input.contact_rebuild = ContactRebuild::kFull;
    workload += "_full_contact_rebuilds";
  }
  if (opt.bond_threads > 0) {
    input.bond_threads = opt.bond_threads;
    workload += "_threads" + std::to_string(opt.bond_threads);
  }
  if (opt.step_graphs != "auto") {
    input.step_graphs = opt.step_graphs == "on" ? StepGraphs::kOn : StepGraphs::kOff;
    workload += "_graphs_" + opt.step_graphs;
  }
  if (!note.empty()) std::printf("backend    %s\n", note.c_str());
  const auto engine_start = std::chrono::steady_clock::now();
  auto engine = make_engine(backend, input);
  const double scene_seconds = std::chrono::duration<double>(engine_start - setup_start).count();
  const double engine_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - engine_start).count();
  const FamilyStats& fam = engine->family_stats();
  double dt = double(input.step.dt);
  const double family_dt = engine->critical_time_step();
  std::optional<MeasuredStep> measured;  // with ghosts, as `perifrac run` takes it
  if (!opt.scene.empty()) {
    auto_step_within_families(*engine, scene.dt_auto, family_dt, dt);
    measured = measure_ghost_step(*engine, input, scene.dt_auto, critical_dt, dt);
    check_family_time_step(scene, dt, measured ? measured->stable : family_dt, opt.allow_unstable_dt,
                           measured.has_value());
  } else if (dt > family_dt && !opt.allow_unstable_dt) {
    throw std::invalid_argument("bench: the lattice's dt " + std::to_string(dt) +
                                " s exceeds the stable time step of its families, " +
                                std::to_string(family_dt) + " s (allowed: a larger --horizon)");
  }
  engine->advance(opt.warmup);
  engine->stats().reset_times();
  const int64_t screened_before = engine->screened_passes(), graphed_before = engine->graphed_steps();
  const std::vector<RankStats> ranks_before = engine->rank_stats();
  const auto t0 = std::chrono::steady_clock::now();
  profiler_range_push("pd-bench-timed");  // what scripts/profile.sh profiles after a long warm-up
  engine->advance(opt.steps);
  profiler_range_pop();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const int64_t screened = engine->screened_passes() - screened_before;
  const int64_t graphed = engine->graphed_steps() - graphed_before;
  const std::vector<RankStats> ranks = rank_deltas(ranks_before, engine->rank_stats());
  // Whether the workload broke anything: a scene's fracture, or none for the elastic lattice.
  const int64_t broken = engine->broken_bonds();

  const std::string date = utc_now("%Y-%m-%dT%H:%M:%SZ"), rev = git_revision();
  // (Under mpirun the kernel table is rank 0's: its kernels over its own bonds.)
  const int64_t kernel_bonds = ranks.empty() ? fam.bonds : ranks[0].bonds;
  const auto rows = kernel_rows(engine->stats(), "pd/", kernel_bonds, opt.steps, graphed);
  std::printf("bench      %s on %s [%s], %s, git %s\n", workload.c_str(), engine->device_name().c_str(),
              backend_name(backend), date.c_str(), rev.c_str());
  std::printf("size       %zu particles, %lld bonds (mean %.1f per particle), %.1f MiB, %lld steps\n",
              input.particles.size(), (long long)fam.bonds, fam.mean,
              double(engine->memory_bytes()) / (1 << 20), (long long)opt.steps);
  const double stable_dt = measured ? measured->stable : family_dt;
  std::printf("time step  dt %.4g s = %.2f of the %s stable step%s\n", dt, dt / stable_dt,
              measured ? "measured (ghosts)" : "families'",
              dt > stable_dt ? " (unstable, allowed by --allow-unstable-dt)" : "");
  std::printf("set-up     scene %.2f s, engine %.2f s", scene_seconds, engine_seconds);
  if (measured) std::printf(", stable step %.2f s (%d force passes)", measured->seconds, measured->passes);
  std::printf("\n");
  const std::vector<SetupStage> stages = engine->setup_stages();
  if (!stages.empty()) {
    std::printf("set-up     engine stages:");
    for (size_t k = 0; k < stages.size(); ++k)
      std::printf("%s %s %.2f s", k ? "," : "", stages[k].name.c_str(), stages[k].seconds);
    std::printf("\n");
  }
  std::printf("families   %lld of %zu particles find their partners by lattice offset",
              (long long)fam.lattice_particles, input.particles.size());
  if (fam.lattice_listed > 0)
    std::printf(" (%lld of them in the ranks' boundary layers read them from their lists)",
                (long long)fam.lattice_listed);
  if (fam.surface_rows > 0)
    std::printf("; their surface correction in %lld rows of factors", (long long)fam.surface_rows);
  // A slice's threads loop as long as its longest family: the bonds' share of the slots is the
  // share of those iterations that visit a bond (spread family sizes lower it).
  if (fam.slots > 0)
    std::printf("; bonds fill %.1f%% of the %d-wide slices", 100.0 * double(fam.bonds) / double(fam.slots),
                kSliceWidth);
  std::printf("\n");
  print_kernel_table(std::cout, rows);
  if (backend == Backend::kCuda)
    std::printf("timing     each kernel's time from one launch in %lld, timed with CUDA events\n",
                (long long)kTimedLaunchStride);
  std::printf("screened   springforces ran without the breaking path in %lld of the %lld steps\n",
              (long long)screened, (long long)opt.steps);
  if (graphed > 0)
    std::printf(
        "graphs     %lld of the %lld steps ran as CUDA graphs of %d steps, timed as one launch each "
        "(\"%s\"; per-kernel times: --step-graphs off)\n",
        (long long)graphed, (long long)opt.steps, kGraphSteps, kStepGraphStat);
  std::printf("wall       %.3f s for %lld steps: %.3e bond-updates/s end to end\n", wall,
              (long long)opt.steps, double(fam.bonds) * double(opt.steps) / wall);
  std::printf("broken     %lld of %lld bonds after %lld steps (%.4g s simulated, warm-up included)\n",
              (long long)broken, (long long)fam.bonds, (long long)engine->step(), engine->time());
  for (size_t r = 0; r < ranks.size(); ++r) {
    const RankStats& k = ranks[r];
    std::printf(
        "rank %-5zu %lld particles (%lld interior), %lld ghosts: %.3e bond-updates/s, halo (%s%s) %.1f KiB "
        "and %.3f ms per step\n",
        r, (long long)k.particles, (long long)k.interior, (long long)k.ghosts,
        double(k.bonds) * double(opt.steps) / k.step_seconds, k.halo_transport,
        k.overlapped ? ", overlapped" : "", double(k.halo_bytes) / double(opt.steps) / 1024,
        1e3 * k.halo_seconds / double(opt.steps));
  }

  // Results file: one JSON document per run.
  ensure_directory(opt.out);
  std::ostringstream js;
  js << "{\n  \"date\": \"" << date << "\",\n  \"git\": \"" << rev << "\",\n  \"device\": \""
     << json_escape(engine->device_name()) << "\",\n  \"backend\": \"" << backend_name(backend)
     << "\",\n  \"precision\": \"" << (sizeof(real) == 4 ? "float32" : "float64") << "\",\n  \"workload\": \""
     << workload << "\",\n  \"particles\": " << input.particles.size() << ",\n  \"bonds\": " << fam.bonds
     << ",\n  \"lattice_particles\": " << fam.lattice_particles
     << ",\n  \"lattice_listed_particles\": " << fam.lattice_listed
     << ",\n  \"surface_rows\": " << fam.surface_rows << ",\n  \"bond_slots\": " << fam.slots
     << ",\n  \"steps\": " << opt.steps << ",\n  \"screened_steps\": " << screened
     << ",\n  \"graphed_steps\": " << graphed << ",\n  \"dt\": " << dt
     << ",\n  \"dt_over_stable\": " << dt / stable_dt << ",\n  \"broken_bonds\": " << broken
     << ",\n  \"simulated_seconds\": " << engine->time() << ",\n  \"wall_seconds\": " << wall
     << ",\n  \"setup_seconds\": {\"scene\": " << scene_seconds << ", \"engine\": " << engine_seconds
     << ", \"engine_stages\": {" << stage_json(stages) << "}}"
     << ",\n  \"kernels\": [\n";
  for (size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    js << "    {\"name\": \"" << r.name << "\", \"launches\": " << r.launches
       << ", \"seconds\": " << r.seconds << ", \"ms_per_launch\": " << r.ms_per_launch
       << ", \"share\": " << r.share << ", \"bond_updates_per_s\": " << r.bond_updates_per_s
       << ", \"registers\": " << r.registers << ", \"occupancy\": " << r.occupancy << "}"
       << (k + 1 < rows.size() ? "," : "") << "\n";
  }
  js << "  ],\n  \"ranks\": [\n";
  for (size_t r = 0; r < ranks.size(); ++r) {
    const RankStats& k = ranks[r];
    js << "    {\"rank\": " << r << ", \"particles\": " << k.particles << ", \"ghosts\": " << k.ghosts
       << ", \"bonds\": " << k.bonds << ", \"step_seconds\": " << k.step_seconds
       << ", \"bond_updates_per_s\": " << double(k.bonds) * double(opt.steps) / k.step_seconds
       << ", \"halo_bytes_per_step\": " << double(k.halo_bytes) / double(opt.steps)
       << ", \"halo_exchanges_per_step\": " << double(k.halo_exchanges) / double(opt.steps)
       << ", \"halo_seconds_per_step\": " << k.halo_seconds / double(opt.steps)
       << ", \"interior\": " << k.interior << ", \"halo_transport\": \"" << k.halo_transport
       << "\", \"overlapped\": " << (k.overlapped ? "true" : "false") << "}"
       << (r + 1 < ranks.size() ? "," : "") << "\n";
  }
  js << "  ]\n}\n";
  const std::string file =
      opt.out + "/" + utc_now("%Y%m%d-%H%M%S") + "_" + backend_name(backend) + "_" + workload + ".json";
  write_file_atomic(file, js.str());
  std::printf("results    %s\n", file.c_str());
  return kExitOk;
}

}  // namespace pd
