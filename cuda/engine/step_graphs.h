// CUDA graphs of the step: where nothing on the host falls between a step's launches, the GPU
// engine records kGraphSteps steps' launches once into a graph and then runs them as one launch
// (cuda/engine/engine_impl.h), which small scenes, bound by launches, run faster. The graph runs
// the same kernels on the same arguments in the same order: the bits are those of the launches.
// Launches, graphed or not, overlap the last blocks of the one before them on the GPU
// (overlapped_launches_wanted).
#pragma once

#include <cstdint>

#include "cuda/engine/particle_set.h"

namespace pd {

// Steps per graph: a step's launches (8 to 10) times this is one graph launch.
constexpr int kGraphSteps = 32;

// The kernel-stats entry of the graphs' launches: their kernels are timed together.
constexpr const char* kStepGraphStat = "pd/step graph";

// Scenes with fewer particles use graphs when the run leaves the choice to the engine (kAuto):
// below it graphs gain from 3% (512k lattice) to 2.2x (3,840-particle bar) on an H200; at 1M
// particles they are within 2% either way (bench/REPORT.md, "CUDA graphs of the step").
constexpr int64_t kGraphParticles = int64_t(1) << 19;

// What a run of `in` asks for: in.step_graphs where not kAuto, else the environment's
// PERIFRAC_STEP_GRAPHS (auto, on or off), else kAuto. std::invalid_argument names a bad value.
StepGraphs requested_step_graphs(const SimulationInput& in);

// Whether the run of `in` runs its step as graphs where its scene allows them (the engine also
// needs a step without host work: no scripted motion, free bodies, moving colliders, contact
// lists, projectiles or ranks): asked for (kOn), or left to the engine (kAuto) below
// kGraphParticles particles.
bool step_graphs_wanted(const SimulationInput& in);

// Whether the GPU's launches overlap their predecessor's last blocks (programmatic dependent
// launch, cuda/exec_cuda.cuh): on, unless the environment's PERIFRAC_OVERLAP_LAUNCHES is off (the
// launches in turn, for comparison: the same bits). std::invalid_argument names a bad value.
bool overlapped_launches_wanted();

}  // namespace pd
