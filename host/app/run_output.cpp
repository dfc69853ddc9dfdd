#include "host/app/run_output.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>

#include "host/io/frame_file.h"

namespace pd {

bool output_thread_wanted() {
  const char* v = std::getenv("PERIFRAC_OUTPUT_THREAD");
  if (!v || std::string(v) == "1") return true;
  if (std::string(v) == "0") return false;
  throw std::invalid_argument("PERIFRAC_OUTPUT_THREAD='" + std::string(v) + "' (allowed: 0 or 1)");
}

std::chrono::steady_clock::time_point lap(std::chrono::steady_clock::time_point t, double& into) {
  const auto now = std::chrono::steady_clock::now();
  into += std::chrono::duration<double>(now - t).count();
  return now;
}

namespace {

// One frame's per-particle data from its state `s` into `f` (the memory of `f` and `s` kept from
// frame to frame: a frame's vectors are as long as the last one's).
void frame_data_from(const ParticleSet& ps, const std::vector<int32_t>& count, ParticleState& s,
                     FrameData& f) {
  f.position.resize(ps.size());
  f.damage.resize(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    f.position[i] = ps.rest[i] + s.disp[i];
    f.damage[i] = count[i] > 0 ? 1.0f - float(s.intact[i]) / float(count[i]) : 0.0f;
  }
  std::swap(f.velocity, s.vel);  // (`s` keeps the frame's old memory for the next read)
  f.body.assign(ps.body.begin(), ps.body.end());
  f.component.clear();
}

// The Voronoi bodies' cells, the elements of their particles.
std::vector<VoronoiElements> voronoi_elements(const SetupResult& setup) {
  std::vector<VoronoiElements> elements;
  for (const VoronoiBody& v : setup.voronoi) elements.push_back({v.first_particle, &v.geometry});
  return elements;
}

}  // namespace

// A frame on its way: taken by the frame loop (its read-back started), read and analysed on the
// first thread, written on the second.
struct RunOutput::Frame {
  int64_t frame = 0;
  std::unique_ptr<FrameRead> read;  // until the first thread finishes it into `data` and `changes`
  FrameData data;
  bool bonds_changed = false;  // frames after the first: `changes` brings the bonds to this frame
  BondChanges changes;
  Energy energy;
  std::vector<Collider> colliders;
  std::function<void(const std::string&)> done;
  ComponentStats stats;
  FragmentFiles files;
};

RunOutput::RunOutput(const Scene& scene, const SetupResult& setup, Engine& engine, Backend backend,
                     int blend_frames, RunFolder& folder)
    : scene_(scene),
      setup_(setup),
      engine_(engine),
      particles_(setup.input.particles),
      folder_(folder),
      out_(folder.dir()),
      blend_frames_(blend_frames),
      live_(scene.render && scene.render->every > 0
                ? std::make_unique<LiveRender>(scene, out_, backend_name(backend))
                : nullptr),
      series_(out_, "particles"),
      energy_log_(out_ + "/energy.csv"),
      fragment_csv_(out_ + "/" + kFragmentLogFileName),
      colliders_(out_, setup.input, setup.collider_meshes, scene.write_vtk) {
  // The bonds as built (before the first step or a restore), which later frames' changes update.
  BondChanges built;
  engine.bond_changes(std::numeric_limits<size_t>::max(), built);
  bonds_ = std::move(built.bonds);
  count_ = bonds_.count;
  slots_ = bonds_.neighbor.size();
  // A frame's outputs, queued while the engine steps on: the frames ahead are bounded by memory.
  const size_t frame_bytes =
      particles_.size() * (2 * sizeof(Vec3) + sizeof(float) + sizeof(int32_t)) + slots_ / 8 + 1;
  frames_ahead_ = std::clamp<size_t>(kOutputQueueBytes / frame_bytes, 1, kMostFramesAhead);
  // The fragment outputs are set up on the first thread, beside frame 0 and the first steps.
  if (!threaded_) {
    set_up_fragments();
    return;
  }
  analysing_ = std::thread([this] {
    try {
      set_up_fragments();
    } catch (...) {
      fail(std::current_exception());
    }
  });
}

void RunOutput::set_up_fragments() {
  const auto start = std::chrono::steady_clock::now();
  fragments_ =
      std::make_unique<FragmentOutput>(setup_.input, bonds_, FragmentOutputOptions{out_, blend_frames_},
                                       setup_.adjacency, setup_.embedded, voronoi_elements(setup_));
  if (const FaceLinks& links = fragments_->face_links(); links.indirect() + links.unlinked() > 0)
    std::printf(
        "elements   %zu touching pairs farther apart than the horizon: %zu hold through common "
        "neighbours, %zu have no bond path (cracks from the start)\n",
        links.indirect() + links.unlinked(), links.indirect(), links.unlinked());
  lap(start, times_.setup);
}

RunOutput::~RunOutput() {
  if (analysing_.joinable()) analysing_.join();
  if (writing_.joinable()) writing_.join();
}

void RunOutput::write_frame(int64_t frame, const Energy& energy,
                            std::function<void(const std::string&)> done) {
  wait_for_room();
  std::shared_ptr<Frame> job = spare_frame();
  job->frame = frame;
  job->energy = energy;
  job->data.frame = frame;
  job->data.step = engine_.step();
  job->data.time = engine_.time();
  job->bonds_changed = frame > 0;
  job->read = engine_.read_frame(slots_, job->bonds_changed);
  job->colliders = engine_.colliders();
  job->done = std::move(done);
  if (!threaded_) {
    analyse(*job);
    write(*job);
    return keep_spare(std::move(job));
  }
  // The first thread: after the previous frame's analysis (and the set-up), this one's, unless a
  // frame failed (no later frame is made after one). Then, after the previous frame's writing,
  // the second thread writes this frame.
  auto analysed = std::make_shared<std::promise<void>>();
  in_flight_.push_back(analysed->get_future());
  analysing_ = std::thread([this, job, analysed, previous = std::move(analysing_)]() mutable {
    if (previous.joinable()) previous.join();
    if (!failure()) {
      try {
        analyse(*job);
      } catch (...) {
        fail(std::current_exception());
      }
    }
    if (writing_.joinable()) writing_.join();
    if (!failure())
      writing_ = std::thread([this, job]() mutable {
        try {
          write(*job);
          keep_spare(std::move(job));
        } catch (...) {
          fail(std::current_exception());
        }
      });
    analysed->set_value();
  });
}

void RunOutput::analyse(Frame& job) {
  const auto start = std::chrono::steady_clock::now();
  job.read->finish(state_, job.changes);
  job.read.reset();
  frame_data_from(particles_, count_, state_, job.data);
  const auto read = lap(start, times_.read_back);
  if (job.bonds_changed) job.changes.apply_to(bonds_);
  job.stats = fragments_->analyse(job.data, bonds_);
  auto t = lap(read, times_.analysis);
  job.files = fragments_->files_of(job.data);
  t = lap(t, times_.crack_surfaces);
  times_.longest_analysis =
      std::max(times_.longest_analysis, std::chrono::duration<double>(t - read).count());
}

void RunOutput::write(Frame& job) {
  const auto start = std::chrono::steady_clock::now();
  const FrameData& f = job.data;
  folder_.begin_frame(job.frame);
  // The frame files beside the fragment files (all independent atomic files).
  std::future<void> frame_files = std::async(std::launch::async, [&] {
    const auto t = std::chrono::steady_clock::now();
    if (scene_.write_binary) write_frame_file(out_ + "/" + frame_file_name(job.frame, "pfr"), f);
    if (scene_.write_vtk) write_vtu(out_ + "/" + frame_file_name(job.frame, "vtu"), f);
    lap(t, times_.frame_files);
  });
  try {
    const auto t = std::chrono::steady_clock::now();
    fragments_->write_files(f, job.files);
    lap(t, times_.fragment_files);
  } catch (...) {
    frame_files.wait();  // (it reads `job`)
    throw;
  }
  frame_files.get();
  if (scene_.write_vtk) series_.add(f.time, frame_file_name(job.frame, "vtu"));
  fragment_csv_.add(job.frame, f.step, f.time, job.stats);
  // The energy log, after the frame's files: each of its atomic rewrites syncs a file, which
  // while the frames' files are written took 10 ms a frame on the frame loop (bench/NOTES.md).
  energy_log_.add(job.frame, f.step, f.time, job.energy);
  colliders_.write_frame(job.frame, f.time, job.colliders);
  if (live_) live_->frame(job.frame);
  folder_.frame_done(job.frame);
  if (job.done) job.done(format_component_stats(job.stats));
  double writing = 0;
  lap(start, writing);
  times_.writing += writing;
  times_.longest_writing = std::max(times_.longest_writing, writing);
  ++times_.frames;
}

std::shared_ptr<RunOutput::Frame> RunOutput::spare_frame() {
  const std::lock_guard<std::mutex> lock(spare_mutex_);
  if (spare_.empty()) return std::make_shared<Frame>();
  std::shared_ptr<Frame> job = std::move(spare_.back());
  spare_.pop_back();
  return job;
}

void RunOutput::keep_spare(std::shared_ptr<Frame> job) {
  job->done = {};
  job->files = {};  // (the crack surface: a new one each frame)
  const std::lock_guard<std::mutex> lock(spare_mutex_);
  if (spare_.size() < kMostSpareFrames) spare_.push_back(std::move(job));
}

void RunOutput::fail(std::exception_ptr e) {
  const std::lock_guard<std::mutex> lock(failure_mutex_);
  if (!failure_) failure_ = e;
}

std::exception_ptr RunOutput::failure() {
  const std::lock_guard<std::mutex> lock(failure_mutex_);
  return failure_;
}

void RunOutput::wait_for_room() {
  while (in_flight_.size() >= frames_ahead_) {
    in_flight_.front().wait();
    in_flight_.pop_front();
  }
  if (const std::exception_ptr e = failure()) std::rethrow_exception(e);  // a frame's outputs failed
}

void RunOutput::drain() {
  if (analysing_.joinable()) analysing_.join();
  if (writing_.joinable()) writing_.join();
  in_flight_.clear();
  if (std::exception_ptr e = failure()) {
    failure_ = nullptr;
    std::rethrow_exception(e);
  }
}

void RunOutput::restore(RunCheckpoint& c) {
  drain();  // (the fragment outputs set up)
  fragments_->smoother().restore(std::move(c.smoother));
  colliders_.restore(c.series);
  series_.restore(std::move(c.series));
  energy_log_.restore(std::move(c.energy_log));
  if (!c.fragment_log.empty()) fragment_csv_.restore(std::move(c.fragment_log));
}

void RunOutput::save(RunCheckpoint& c) {
  drain();
  c.energy_log = energy_log_.text();
  c.fragment_log = fragment_csv_.text();
  c.series = series_.entries();
  c.smoother = fragments_->smoother().history();
}

void RunOutput::finish_complete_run() {
  drain();
  engine_.read_bonds(bonds_);
  fragments_->find_components(bonds_);
  fragments_->write_meshes();
}

void RunOutput::finish() {
  drain();
  if (live_) live_->finish();
  fragments_->write_meshes();
}

}  // namespace pd
