// `perifrac shapes SCENE`: writes the solid of each body of a scene as a mesh file, so the
// procedural shapes (box, plate, sphere, cylinder, torus, vase) and the checked, repaired and
// placed mesh bodies can be opened elsewhere (Blender, ParaView, another renderer) or reused as a
// `mesh` body. One file per body, named after it, in rest space at the body's place.
#pragma once

#include <string>
#include <vector>

namespace pd {

struct ShapeExportOptions {
  std::string scene;
  std::string out = "shapes";          // folder, created when missing
  std::string format = "obj";          // obj | ply | stl (binary PLY and STL)
  double edge = 0;                     // vertex spacing of curved surfaces [m]; 0: each body's spacing
  std::vector<std::string> overrides;  // --set KEY=VALUE, as for `perifrac run`
};

// Returns the exit code; throws SceneError, MeshError or IoError (the CLI reports them).
int export_shapes_command(const ShapeExportOptions& options);

}  // namespace pd
