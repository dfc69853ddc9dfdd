#include "fragment_output.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "cube_mesh.h"
#include "fragments_file.h"
#include "ply_points.h"

namespace pd {

FragmentOutput::FragmentOutput(const SimulationInput& input, const BondLists& bonds,
                               FragmentOutputOptions options, ElementAdjacency adjacency)
    : options_(std::move(options)),
      rest_(input.particles.rest),
      mass_(input.particles.mass),
      spacing_(particle_spacing(input.particles, input.materials)),
      adjacency_(adjacency.size() == rest_.size() ? std::move(adjacency)
                                                  : grid_adjacency(bonds, rest_, spacing_)),
      finder_(adjacency_, bonds),
      smoother_(options_.blend_frames) {}

ComponentStats FragmentOutput::process(FrameData& f, const BondLists& bonds) {
  if (f.size() != rest_.size())
    throw std::invalid_argument("FragmentOutput::process: the frame has " + std::to_string(f.size()) +
                                " particles, the run " + std::to_string(rest_.size()));
  // Components, then one rigid fit per component, blended across splits.
  finder_.find(bonds, components_);
  f.component = components_.id;
  align_fragments(components_, rest_, f.position, mass_, fragments_);
  smoother_.apply(components_, rest_, f.position, mass_, fragments_);
  // Files of the frame.
  write_fragments_file(options_.dir + "/" + fragments_file_name(f.frame), f.frame, f.step, f.time,
                       fragments_);
  if (options_.points) write_ply_points(options_.dir + "/" + points_file_name(f.frame), f);
  return component_stats(components_);
}

bool FragmentOutput::write_meshes(const std::string& name) const {
  if (components_.count() == 0) throw std::logic_error("FragmentOutput::write_meshes before the first frame");
  if (!options_.cube_meshes) return false;
  write_obj(options_.dir + "/" + name, cube_fragment_mesh(adjacency_, rest_, spacing_, components_));
  return true;
}

}  // namespace pd
