#include "host/app/export_shapes.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "host/app/run.h"
#include "host/geometry/mesh_io.h"
#include "host/io/atomic_file.h"
#include "host/scene/scene_setup.h"

namespace pd {

int export_shapes_command(const ShapeExportOptions& o) {
  const Scene scene = load_scene(o.scene, o.overrides);
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (ec) throw io_error("create", o.out, ec.message());
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const SceneBody& body = scene.bodies[b];
    const std::string key = "bodies[" + std::to_string(b) + "]";
    const double edge = o.edge > 0 ? o.edge : body_solid_edge(body, body.spacing);
    TriMesh mesh;
    try {
      mesh = body_solid(body, edge, key);
    } catch (const MeshError& e) {
      throw SceneError(scene.path, key + ".mesh", e.what());
    }
    // (Bodies of one name, which the scene allows with a warning, get their index too.)
    const bool shared = std::count_if(scene.bodies.begin(), scene.bodies.end(),
                                      [&](const SceneBody& x) { return x.name == body.name; }) > 1;
    const std::string path =
        o.out + "/" + body.name + (shared ? "_" + std::to_string(b) : "") + "." + o.format;
    if (o.format == "obj") write_obj(mesh, path);
    if (o.format == "ply") write_ply(mesh, path, true);
    if (o.format == "stl") write_stl(mesh, path, true);
    const bool sheet = body_solid_is_sheet(body);
    std::printf("%-16s %-9s %8zu triangles  %s %.6g m%s  %s\n", body.name.c_str(), body.shape.c_str(),
                mesh.triangles.size(), sheet ? "area  " : "volume",
                sheet ? surface_area(mesh) : signed_volume(mesh),
                sheet ? "^2 (the shell's outer surface)" : "^3", path.c_str());
  }
  return kExitOk;
}

}  // namespace pd
