#include "host/fragments/fragment_output.h"

#include <chrono>
#include <cstdio>
#include <future>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/fragments/fragments_file.h"
#include "host/fragments/piece_mesh.h"
#include "host/fragments/ply_points.h"

namespace pd {

FragmentOutput::FragmentOutput(const SimulationInput& input, const BondLists& bonds,
                               FragmentOutputOptions options, ElementAdjacency adjacency,
                               const EmbeddedTets& tets, const std::vector<VoronoiElements>& voronoi)
    : options_(std::move(options)),
      rest_(input.particles.rest),
      mass_(input.particles.mass),
      spacing_(particle_spacing(input.particles, input.materials)),
      adjacency_(adjacency.size() == rest_.size() ? std::move(adjacency)
                                                  : grid_adjacency(bonds, rest_, spacing_)),
      finder_(adjacency_, bonds),
      smoother_(options_.blend_frames),
      embedded_(particle_elements(rest_, spacing_, adjacency_, tets, voronoi), adjacency_, bonds, rest_,
                mass_) {}

ComponentStats FragmentOutput::process(FrameData& f, const BondLists& bonds) {
  const ComponentStats stats = analyse(f, bonds);
  FragmentFiles files = files_of(f);
  write_files(f, files);
  crack_surface_ = std::move(files.crack_surface);
  return stats;
}

ComponentStats FragmentOutput::analyse(FrameData& f, const BondLists& bonds) {
  if (f.size() != rest_.size())
    throw std::invalid_argument("FragmentOutput::analyse: the frame has " + std::to_string(f.size()) +
                                " particles, the run " + std::to_string(rest_.size()));
  // Each stage's time added to times_ as it ends.
  auto t = std::chrono::steady_clock::now();
  const auto lap = [&t](double& into) {
    const auto now = std::chrono::steady_clock::now();
    into += std::chrono::duration<double>(now - t).count();
    t = now;
  };
  // Components, then one rigid fit per component, blended across splits.
  finder_.find(bonds, components_);
  f.component = components_.id;
  lap(times_.components);
  align_fragments(components_, rest_, f.position, mass_, fragments_);
  lap(times_.fits);
  // The embedded mesh: split along this frame's cracks, placed by the particles and the fits.
  if (options_.crack_meshes) embedded_.update(bonds, f.position, components_, fragments_);
  lap(times_.crack_mesh);
  smoother_.apply(components_, rest_, f.position, mass_, fragments_);
  lap(times_.blending);
  ComponentStats stats = component_stats(components_, mass_, &bonds);
  lap(times_.statistics);
  return stats;
}

FragmentFiles FragmentOutput::files_of(const FrameData& f) const {
  FragmentFiles files;
  files.fragments = fragments_;
  if (options_.crack_meshes) {
    embedded_.surface(files.crack_surface);
    char text[96];
    std::snprintf(text, sizeof text, "frame %lld step %lld time %.17g", (long long)f.frame, (long long)f.step,
                  f.time);
    files.comment = text;
  }
  return files;
}

void FragmentOutput::write_files(const FrameData& f, const FragmentFiles& files) const {
  // Each file is an atomic file of its own, synced to disk, written side by side: a shattered
  // body's crack meshes take most of a frame's output time (bench/REPORT.md).
  std::vector<std::future<void>> writes;
  const auto write = [&writes](auto&& job) { writes.push_back(std::async(std::launch::async, job)); };
  write([&] {
    write_fragments_file(options_.dir + "/" + fragments_file_name(f.frame), f.frame, f.step, f.time,
                         files.fragments);
  });
  if (options_.points) write([&] { write_ply_points(options_.dir + "/" + points_file_name(f.frame), f); });
  if (options_.crack_meshes) {
    write([&] {
      write_crack_obj(options_.dir + "/" + crack_mesh_file_name(f.frame, "obj"), files.crack_surface,
                      files.comment);
    });
    write([&] {
      write_crack_ply(options_.dir + "/" + crack_mesh_file_name(f.frame, "ply"), files.crack_surface,
                      files.comment);
    });
  }
  for (std::future<void>& w : writes) w.get();  // each finished; the first failure thrown
}

void FragmentOutput::write_meshes(const std::string& name) const {
  if (components_.count() == 0) throw std::logic_error("FragmentOutput::write_meshes before the first frame");
  write_obj(options_.dir + "/" + name, fragment_pieces(embedded_.elements(), components_));
}

}  // namespace pd
