#include "host/app/run_output.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
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

// One frame's per-particle data from the engine (`s`: memory kept from frame to frame).
FrameData frame_data(Engine& engine, const ParticleSet& ps, const std::vector<int32_t>& count, int64_t frame,
                     ParticleState& s) {
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

// The engine's bonds as built, before the first step.
BondLists bonds_as_built(Engine& engine) {
  BondLists bonds;
  engine.read_bonds(bonds);
  return bonds;
}

// The Voronoi bodies' cells, the elements of their particles.
std::vector<VoronoiElements> voronoi_elements(const SetupResult& setup) {
  std::vector<VoronoiElements> elements;
  for (const VoronoiBody& v : setup.voronoi) elements.push_back({v.first_particle, &v.geometry});
  return elements;
}

}  // namespace

// A frame on its way: read back by the frame loop, analysed on the first thread, written on the
// second.
struct RunOutput::Frame {
  int64_t frame = 0;
  FrameData data;
  Energy energy;
  std::vector<Collider> colliders;
  std::function<void(const std::string&)> done;
  ComponentStats stats;
  FragmentFiles files;
};

RunOutput::RunOutput(const Scene& scene, const SetupResult& setup, Engine& engine, Backend backend,
                     int blend_frames, RunFolder& folder)
    : scene_(scene),
      engine_(engine),
      particles_(setup.input.particles),
      folder_(folder),
      out_(folder.dir()),
      live_(scene.render && scene.render->every > 0
                ? std::make_unique<LiveRender>(scene, out_, backend_name(backend))
                : nullptr),
      series_(out_, "particles"),
      bonds_(bonds_as_built(engine)),
      fragments_(setup.input, bonds_, {out_, blend_frames}, setup.adjacency, setup.embedded,
                 voronoi_elements(setup)),
      energy_log_(out_ + "/energy.csv"),
      fragment_csv_(out_ + "/" + kFragmentLogFileName),
      colliders_(out_, setup.input, setup.collider_meshes, scene.write_vtk) {
  if (const FaceLinks& links = fragments_.face_links(); links.indirect() + links.unlinked() > 0)
    std::printf(
        "elements   %zu touching pairs farther apart than the horizon: %zu hold through common "
        "neighbours, %zu have no bond path (cracks from the start)\n",
        links.indirect() + links.unlinked(), links.indirect(), links.unlinked());
}

RunOutput::~RunOutput() {
  if (analysing_.joinable()) analysing_.join();
  if (writing_.joinable()) writing_.join();
}

void RunOutput::write_frame(int64_t frame, const Energy& energy,
                            std::function<void(const std::string&)> done) {
  wait_for_bonds();
  auto job = std::make_shared<Frame>();
  job->frame = frame;
  job->energy = energy;
  job->data = frame_data(engine_, particles_, bonds_.count, frame, state_);
  if (frame > 0) engine_.update_bonds(bonds_);
  job->colliders = engine_.colliders();
  job->done = std::move(done);
  if (!threaded_) {
    analyse(*job, [] {});
    return write(*job);
  }
  // The first thread: after the previous frame's analysis, this one's; the bonds are released
  // once its fragments are found, or with the first failure (no later frame is made after one).
  // Then, after the previous frame's writing, the second thread writes this frame.
  auto released = std::make_shared<std::promise<void>>();
  bonds_released_ = released->get_future();
  analysing_ = std::thread([this, job, released, previous = std::move(analysing_)]() mutable {
    if (previous.joinable()) previous.join();
    bool given = false;
    if (!failure()) {
      try {
        analyse(*job, [&] {
          released->set_value();
          given = true;
        });
      } catch (...) {
        fail(std::current_exception());
      }
    }
    if (writing_.joinable()) writing_.join();
    const std::exception_ptr failed = failure();
    if (!given) released->set_exception(failed);
    if (failed) return;
    writing_ = std::thread([this, job] {
      try {
        write(*job);
      } catch (...) {
        fail(std::current_exception());
      }
    });
  });
}

void RunOutput::analyse(Frame& job, const std::function<void()>& release_bonds) {
  const auto start = std::chrono::steady_clock::now();
  job.stats = fragments_.analyse(job.data, bonds_);
  auto t = lap(start, times_.analysis);
  release_bonds();
  job.files = fragments_.files_of(job.data);
  t = lap(t, times_.crack_surfaces);
  times_.longest_analysis =
      std::max(times_.longest_analysis, std::chrono::duration<double>(t - start).count());
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
    fragments_.write_files(f, job.files);
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

void RunOutput::fail(std::exception_ptr e) {
  const std::lock_guard<std::mutex> lock(failure_mutex_);
  if (!failure_) failure_ = e;
}

std::exception_ptr RunOutput::failure() {
  const std::lock_guard<std::mutex> lock(failure_mutex_);
  return failure_;
}

void RunOutput::wait_for_bonds() {
  if (bonds_released_.valid()) bonds_released_.get();
  if (const std::exception_ptr e = failure()) std::rethrow_exception(e);  // a frame's writing failed
}

void RunOutput::drain() {
  if (analysing_.joinable()) analysing_.join();
  if (writing_.joinable()) writing_.join();
  bonds_released_ = {};
  if (std::exception_ptr e = failure()) {
    failure_ = nullptr;
    std::rethrow_exception(e);
  }
}

void RunOutput::restore(RunCheckpoint& c) {
  fragments_.smoother().restore(std::move(c.smoother));
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
  c.smoother = fragments_.smoother().history();
}

void RunOutput::finish_complete_run() {
  drain();
  engine_.read_bonds(bonds_);
  fragments_.find_components(bonds_);
  fragments_.write_meshes();
}

void RunOutput::finish() {
  drain();
  if (live_) live_->finish();
  fragments_.write_meshes();
}

}  // namespace pd
