#include "host/scene/scene_smells.h"

#include <cmath>
#include <cstdio>

namespace pd {

std::vector<std::string> scene_smells(const Scene& scene, const SimulationInput& in,
                                      const std::vector<std::string>& body_names) {
  std::vector<std::string> out;
  char line[512];
  const ParticleSet& ps = in.particles;
  // Anchors that hold nothing.
  std::vector<int64_t> held(scene.anchors.size(), 0);
  for (size_t i = 0; i < ps.size(); ++i)
    if ((ps.flags[i] & kAnchored) && ps.anchor[i] < held.size()) ++held[ps.anchor[i]];
  for (size_t g = 0; g < held.size(); ++g)
    if (held[g] == 0) {
      const std::string whose =
          scene.anchors[g].body.empty() ? "" : " of body '" + scene.anchors[g].body + "'";
      std::snprintf(line, sizeof line,
                    "warning: anchors[%zu]: its box holds no particle%s, so it does nothing", g,
                    whose.c_str());
      out.push_back(line);
    }
  // Bodies of one name: an anchor, crack or region naming it takes all of them.
  for (size_t a = 0; a < scene.bodies.size(); ++a)
    for (size_t b = a + 1; b < scene.bodies.size(); ++b)
      if (scene.bodies[a].name == scene.bodies[b].name) {
        std::snprintf(line, sizeof line,
                      "warning: bodies[%zu] and bodies[%zu] are both named '%s': an anchor, crack or region "
                      "naming it takes both",
                      a, b, scene.bodies[a].name.c_str());
        out.push_back(line);
      }
  // Particles whose centre starts below the floor: thrown up at the first step.
  if (scene.floor) {
    std::vector<int64_t> below(body_names.size(), 0);
    for (size_t i = 0; i < ps.size(); ++i)
      if (double(ps.rest[i].y) < scene.floor_height) ++below[size_t(ps.body[i])];
    for (size_t b = 0; b < below.size(); ++b)
      if (below[b] > 0) {
        std::snprintf(line, sizeof line,
                      "warning: body '%s': %lld particles start below the floor (y = %g), which throws them "
                      "up at once",
                      body_names[b].c_str(), (long long)below[b], scene.floor_height);
        out.push_back(line);
      }
  }
  return out;
}

}  // namespace pd
