// Embree 3 (Apache-2.0) as the renderer's test oracle and benchmark baseline, built only when
// CMake finds it (PERIFRAC_HAS_EMBREE): the primitives triangulated into one triangle mesh
// (cubes and oriented cubes 12 triangles, tetrahedra 4), built with Embree's high-quality BVH,
// and traced one ray at a time with rtcIntersect1.
#pragma once

#include <string>
#include <vector>

#include "render/camera.h"
#include "render/primitive_set.h"

namespace pd {

class EmbreeScene {
 public:
  // Throws std::invalid_argument for trimtopes (no triangulation here) and std::runtime_error
  // when Embree fails.
  explicit EmbreeScene(const PrimitiveSet& prims);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  static std::string version();  // "3.13.5"
  double build_seconds() const { return build_seconds_; }
  size_t triangles() const { return triangles_; }

  // The nearest triangle crossing of o + t d with t in [tnear, tfar] (Embree's rule); INFINITY
  // for a miss.
  float nearest(Vec3 o, Vec3 d, float tnear = 0, float tfar = INFINITY) const;

  // One ray per sample of every pixel (the renderer's camera rays, camera.h), in parallel over
  // rows with OpenMP: the nearest t of sample 0 per pixel (row major; INFINITY: miss) and the
  // wall time of the loop.
  struct PrimaryTrace {
    std::vector<float> depth;
    double seconds = 0;
  };
  PrimaryTrace trace_primary(const CameraFrame& camera, int spp) const;

 private:
  void* device_ = nullptr;  // RTCDevice
  void* scene_ = nullptr;   // RTCScene
  double build_seconds_ = 0;
  size_t triangles_ = 0;
};

}  // namespace pd
