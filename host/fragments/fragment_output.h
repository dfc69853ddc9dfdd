// The fragment outputs of a run in one object for the frame loop: per frame it finds the
// components, fills FrameData::component, fits and smooths the fragment transforms and writes
// fragments_NNNNN.pfg and points_NNNNN.ply, and the split embedded mesh of the particles'
// elements (crack_mesh_NNNNN.obj / .ply, Chen sec. 5.2); at the end it writes the rest-space
// piece surfaces (fragments.obj). Elements: cubes for grid bodies, the tets of tet bodies, the
// clipped cells of Voronoi bodies (particle_elements.h). The element adjacency comes from the
// geometry stage, or is derived from the families for grid bodies.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/engine/particle_set.h"
#include "host/fragments/adjacency.h"
#include "host/fragments/align.h"
#include "host/fragments/components.h"
#include "host/fragments/embedded_mesh.h"
#include "host/fragments/particle_elements.h"
#include "host/fragments/smoothing.h"
#include "host/io/frame.h"

namespace pd {

struct FragmentOutputOptions {
  std::string dir;           // output directory (must exist)
  int blend_frames = 0;      // split blending (FragmentSmoother); 0: off
  bool points = true;        // write points_NNNNN.ply
  bool crack_meshes = true;  // write crack_mesh_NNNNN.obj and .ply
};

// What a frame's fragment files are written from (FragmentOutput::files_of).
struct FragmentFiles {
  std::vector<Fragment> fragments;  // the fragments file's transforms
  CrackSurface crack_surface;       // the crack meshes (empty without them)
  std::string comment;              // the crack meshes' comment line
};

class FragmentOutput {
 public:
  // `bonds`: the families as built, before the first step. `adjacency`: the elements that share
  // a face (from the geometry stage); empty: derived from the families as for grid cubes.
  // `tets`, `voronoi`: the tet meshes of tet bodies (SetupResult::embedded) and the Voronoi
  // bodies' cells (SetupResult::voronoi); every other particle is a cube of its material's
  // spacing. Throws std::invalid_argument when the elements do not fit the particles.
  FragmentOutput(const SimulationInput& input, const BondLists& bonds, FragmentOutputOptions options,
                 ElementAdjacency adjacency = {}, const EmbeddedTets& tets = {},
                 const std::vector<VoronoiElements>& voronoi = {});

  // Fragments of frame `f` from the engine's current `bonds`: sets f.component, writes the
  // frame's files and returns the component statistics for the log. Throws IoError when a file
  // cannot be written, std::invalid_argument when `f` or `bonds` do not match the run.
  ComponentStats process(FrameData& f, const BondLists& bonds);
  // process() in three parts, so that a run writes a frame's files while it analyses the next:
  // analyse() is all that reads `bonds` (components, fits, the split embedded mesh, the
  // statistics); files_of() takes what the frame's files need (the fragments, the crack surface);
  // write_files() writes them, reading nothing else of this object but its options.
  ComponentStats analyse(FrameData& f, const BondLists& bonds);
  FragmentFiles files_of(const FrameData& f) const;
  void write_files(const FrameData& f, const FragmentFiles& files) const;

  // Writes <dir>/<name>: the rest-space surfaces of the last processed frame's fragments (OBJ;
  // the last frame's are the finest, as fragments only split). Throws std::logic_error before the
  // first process(), IoError when the file cannot be written.
  void write_meshes(const std::string& name = "fragments.obj") const;

  // What holds the touching elements together (how many hold through common neighbours).
  const FaceLinks& face_links() const { return finder_.links(); }

  // The components of `bonds` without writing anything: a resumed run whose checkpoint is its
  // last frame finishes its end-of-run outputs with this (no frame is processed again).
  void find_components(const BondLists& bonds) { finder_.find(bonds, components_); }

  // Where analyse() has spent its time over the frames so far [s].
  struct AnalysisTimes {
    double components = 0, fits = 0, crack_mesh = 0, blending = 0, statistics = 0;
  };
  const AnalysisTimes& analysis_times() const { return times_; }

  const Components& components() const { return components_; }
  FragmentSmoother& smoother() { return smoother_; }
  const std::vector<Fragment>& fragments() const { return fragments_; }
  // The embedded mesh at the last analysed frame and the crack surface process() last wrote.
  const EmbeddedMesh& embedded_mesh() const { return embedded_; }
  const CrackSurface& crack_surface() const { return crack_surface_; }

 private:
  FragmentOutputOptions options_;
  std::vector<Vec3> rest_;
  std::vector<real> mass_, spacing_;
  ElementAdjacency adjacency_;
  ComponentFinder finder_;
  FragmentSmoother smoother_;
  Components components_;
  std::vector<Fragment> fragments_;
  EmbeddedMesh embedded_;
  CrackSurface crack_surface_;  // the last one process() wrote
  AnalysisTimes times_;
};

}  // namespace pd
