// The per-frame outputs of a run in its output folder (frame files, the VTK series, the fragment
// outputs, the energy log and, with a [render] block, the frames rendered as they come), made in
// a pipeline beside the engine: the frame loop reads a frame back and steps on; a first thread
// finds the frame's fragments (the only stage that reads the bonds) and takes what its files
// need; a second writes them while the first goes on to the next frame. Frames are written in
// order, each file as the serial order writes it (PERIFRAC_OUTPUT_THREAD=0, for measurements).
#pragma once

#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/app/checkpoint.h"
#include "host/app/collider_output.h"
#include "host/app/energy_watch.h"
#include "host/app/live_render.h"
#include "host/app/run_folder.h"
#include "host/fragments/fragment_log.h"
#include "host/fragments/fragment_output.h"
#include "host/io/vtk_writer.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

// PERIFRAC_OUTPUT_THREAD: 1 (the default) makes each frame's outputs on threads of their own
// while the engine steps on; 0 makes them before the next step (for measurements). Another value
// is std::invalid_argument.
bool output_thread_wanted();

// Seconds since `t`, added to `into`; returns now.
std::chrono::steady_clock::time_point lap(std::chrono::steady_clock::time_point t, double& into);

class RunOutput {
 public:
  // Sets up the fragment outputs from the engine's bonds as built (before the first step or a
  // restore) and reports touching elements farther apart than the horizon.
  RunOutput(const Scene& scene, const SetupResult& setup, Engine& engine, Backend backend, int blend_frames,
            RunFolder& folder);
  ~RunOutput();  // waits for the frames being made (an error of a run already failing is dropped)
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  const std::string& dir() const { return out_; }
  RunFolder& folder() { return folder_; }
  size_t fragment_pieces() const { return fragments_.components().count(); }

  // Makes frame `frame`'s outputs from the engine's current state, `energy` its energy. What needs
  // the engine happens now (the frame's particles and bonds read back, the colliders' poses
  // copied); the fragments, files, the energy log's line, rendering, the manifest and then `done`
  // (called with the fragment statistics' line) come on the output threads. Waits first for the
  // previous frame's fragments (wait_for_bonds).
  void write_frame(int64_t frame, const Energy& energy, std::function<void(const std::string&)> done = {});

  // Waits until the frame being analysed no longer reads the bonds; rethrows the failure of a
  // frame's outputs (the first one; no later frame is made after it).
  void wait_for_bonds();

  // Waits for every frame being made; rethrows the first failure.
  void drain();

  // Takes over a checkpoint's fragment smoothing, VTK series and energy log (moved from `c`).
  void restore(RunCheckpoint& c);
  // Puts the energy log, the VTK series and the fragment smoothing into checkpoint `c` (drains).
  void save(RunCheckpoint& c);

  // The end-of-run outputs of a run resumed after its last frame: the fragment pieces of the
  // engine's current bonds.
  void finish_complete_run();
  // The end-of-run outputs: the live render's summary and movie, and the fragment pieces.
  void finish();

  // Where the output threads' time went over the frames made so far (read after drain()).
  struct Times {
    int64_t frames = 0;
    double analysis = 0;          // finding, fitting and splitting (the bonds held), on the first thread
    double crack_surfaces = 0;    // then taking the files' data, the crack surface built
    double writing = 0;           // each frame's writing, start to end, on the second thread
    double fragment_files = 0;    //   of it: the fragment files, side by side with ...
    double frame_files = 0;       //   ... the .pfr and .vtu files
    double longest_analysis = 0;  // the longest frame's analysis and files taken
    double longest_writing = 0;   // the longest frame's writing
  };
  const Times& times() const { return times_; }

 private:
  struct Frame;  // a frame on its way through the output threads
  // The frame's fragments (`release_bonds` called once they no longer need the bonds), then what
  // its files need; on the first thread.
  void analyse(Frame& job, const std::function<void()>& release_bonds);
  // The frame's files, the manifest's record of them, the live render and `done`; on the second.
  void write(Frame& job);
  void fail(std::exception_ptr e);
  std::exception_ptr failure();

  const Scene& scene_;
  Engine& engine_;
  const ParticleSet& particles_;
  RunFolder& folder_;
  std::string out_;
  std::unique_ptr<LiveRender> live_;
  PvdSeries series_;
  ParticleState state_;  // the engine's state as last read back (its memory kept for the next frame)
  BondLists bonds_;
  FragmentOutput fragments_;
  EnergyLog energy_log_;
  FragmentLog fragment_csv_;
  ColliderOutput colliders_;
  bool threaded_ = output_thread_wanted();
  Times times_;                       // each field written by one thread, read after drain()
  std::thread analysing_;             // the last frame given to analyse
  std::thread writing_;               // the last frame given to write (set by the analysing threads)
  std::future<void> bonds_released_;  // the last frame's fragments found (wait_for_bonds)
  std::mutex failure_mutex_;
  std::exception_ptr failure_;  // the first failure of a frame's outputs
};

}  // namespace pd
