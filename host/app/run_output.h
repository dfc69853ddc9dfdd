// The per-frame outputs of a run in its output folder (frame files, the VTK series, the fragment
// outputs, the energy log and, with a [render] block, the frames rendered as they come), made in
// a pipeline beside the engine: the frame loop reads a frame back (its particles, and which bonds
// changed) and steps on; a first thread sets up the fragment outputs, then per frame brings its
// own copy of the bonds up to date, finds the frame's fragments and takes what its files need; a
// second writes them while the first goes on to the next frame. The frame loop runs up to a few
// frames ahead of the first thread (as memory allows). Frames are written in order, each file as
// the serial order writes it (PERIFRAC_OUTPUT_THREAD=0, for measurements).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
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
  // Reads the engine's bonds as built (before the first step or a restore), from which the fragment
  // outputs are set up on the first thread (which reports touching elements farther apart than
  // the horizon).
  RunOutput(const Scene& scene, const SetupResult& setup, Engine& engine, Backend backend, int blend_frames,
            RunFolder& folder);
  ~RunOutput();  // waits for the frames being made (an error of a run already failing is dropped)
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  const std::string& dir() const { return out_; }
  RunFolder& folder() { return folder_; }
  size_t fragment_pieces() const { return fragments_->components().count(); }  // (after finish())
  // The fragments' analysis by stage (after drain()).
  const FragmentOutput::AnalysisTimes& analysis_times() const { return fragments_->analysis_times(); }

  // Makes frame `frame`'s outputs from the engine's current state, `energy` its energy. What needs
  // the engine happens now (the frame's particles and bonds' changes read back, the colliders'
  // poses copied); the fragments, files, the energy log's line, rendering, the manifest and then
  // `done` (called with the fragment statistics' line) come on the output threads. Waits first for
  // room in the queue (wait_for_room).
  void write_frame(int64_t frame, const Energy& energy, std::function<void(const std::string&)> done = {});

  // Waits while the first thread has as many frames ahead of it as the queue holds; rethrows the
  // failure of a frame's outputs (the first one; no later frame is made after it).
  void wait_for_room();

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
    double setup = 0;             // the fragment outputs set up, on the first thread before frame 0
    double read_back = 0;         // waiting for each frame's copies and unpacking them, on the first thread
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
  // The fragment outputs, from the bonds as built; on the first thread.
  void set_up_fragments();
  // The bonds brought to the frame, its fragments, then what its files need; on the first thread.
  void analyse(Frame& job);
  // The frame's files, the manifest's record of them, the live render and `done`; on the second.
  void write(Frame& job);
  // A written frame's memory for the next frame (its vectors keep their length: no new pages to
  // fault in and clear), or a new frame; and a written frame given back, kept up to a few.
  std::shared_ptr<Frame> spare_frame();
  void keep_spare(std::shared_ptr<Frame> job);
  void fail(std::exception_ptr e);
  std::exception_ptr failure();

  // The queue's memory for frames ahead of the first thread, and its most frames.
  static constexpr size_t kOutputQueueBytes = size_t(1) << 30;
  static constexpr size_t kMostFramesAhead = 16;
  static constexpr size_t kMostSpareFrames = 4;  // written frames kept for their memory

  const Scene& scene_;
  const SetupResult& setup_;
  Engine& engine_;
  const ParticleSet& particles_;
  RunFolder& folder_;
  std::string out_;
  int blend_frames_ = 0;
  std::unique_ptr<LiveRender> live_;
  PvdSeries series_;
  ParticleState state_;         // the last frame's state, on the first thread (its memory kept for the next)
  std::vector<int32_t> count_;  // each particle's bonds as built (the frame loop's damage)
  size_t slots_ = 0;            // bond slots as built
  size_t frames_ahead_ = 1;     // frames the frame loop may run ahead of the first thread
  BondLists bonds_;             // the frame being analysed's bonds (the first thread's)
  std::unique_ptr<FragmentOutput> fragments_;  // set up on the first thread
  EnergyLog energy_log_;
  FragmentLog fragment_csv_;
  ColliderOutput colliders_;
  bool threaded_ = output_thread_wanted();
  Times times_;                              // each field written by one thread, read after drain()
  std::thread analysing_;                    // the last frame given to analyse (or the set-up)
  std::thread writing_;                      // the last frame given to write (set by the analysing threads)
  std::deque<std::future<void>> in_flight_;  // the frames given to analyse and not known to be done
  std::mutex spare_mutex_;
  std::vector<std::shared_ptr<Frame>> spare_;  // written frames, their memory kept for the next
  std::mutex failure_mutex_;
  std::exception_ptr failure_;  // the first failure of a frame's outputs
};

}  // namespace pd
