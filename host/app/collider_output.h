// The colliders' outputs of a run: `colliders_NNNNN.csv` (each collider's pose and velocity) at
// every frame; with VTK output also `colliders_NNNNN.vtu` (their posed surfaces) and the series
// `colliders.pvd`; and once `colliders.obj`, each collider's surface in its own frame as an object
// `collider_K`, which the csv's poses move (docs/output-formats.md, the Blender script there).
#pragma once

#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "host/geometry/tri_mesh.h"
#include "host/io/vtk_writer.h"

namespace pd {

class ColliderOutput {
 public:
  // Nothing is written for a scene without colliders. `meshes`: each mesh collider's surface in
  // its frame (SetupResult::collider_meshes).
  ColliderOutput(const std::string& dir, const SimulationInput& in, const std::vector<TriMesh>& meshes,
                 bool write_vtk);

  void write_frame(int64_t frame, double time, const std::vector<Collider>& colliders);
  // A resumed run: the particles' VTK series entries, whose frames this series shares.
  void restore(const std::vector<PvdSeries::Entry>& particle_entries);

 private:
  std::string dir_;
  std::vector<double> masses_;
  std::vector<TriMesh> shapes_;  // each collider's surface in its frame
  bool write_vtk_;
  PvdSeries series_;
};

}  // namespace pd
