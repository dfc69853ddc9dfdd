#include "render/embree_scene.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <stdexcept>
#include <string>

namespace pd {

namespace {

// The 8 corners of a cube (centre c, half side h, axes a) as corner k = (+-, +-, +-) by bits
// of k, and its 12 outward triangles.
void add_cube(std::vector<Vec3>& v, std::vector<uint32_t>& idx, Vec3 c, real h, const Vec3 a[3]) {
  const uint32_t base = uint32_t(v.size());
  for (int k = 0; k < 8; ++k)
    v.push_back(c + ((k & 1) ? h : -h) * a[0] + ((k & 2) ? h : -h) * a[1] + ((k & 4) ? h : -h) * a[2]);
  static const uint32_t faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : faces)
    idx.insert(idx.end(), {base + f[0], base + f[1], base + f[2], base + f[0], base + f[2], base + f[3]});
}

void add_tet(std::vector<Vec3>& v, std::vector<uint32_t>& idx, const Vec3* t) {
  const uint32_t base = uint32_t(v.size());
  v.insert(v.end(), t, t + 4);
  for (uint32_t f = 0; f < 4; ++f)
    idx.insert(idx.end(), {base + (f + 1) % 4, base + (f + 2) % 4, base + (f + 3) % 4});
}

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) +
                             ")");
}

}  // namespace

EmbreeScene::EmbreeScene(const PrimitiveSet& prims) {
  // Triangulate.
  std::vector<Vec3> vertex;
  std::vector<uint32_t> index;
  const PrimitivesView p = prims.view();
  const Vec3 identity[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int32_t i = 0; i < p.n; ++i) {
    const int32_t s = p.slot[i];
    if (p.kind[i] == kPrimCube)
      add_cube(vertex, index, p.cube_center[s], p.cube_half[s], identity);
    else if (p.kind[i] == kPrimOrientedCube)
      add_cube(vertex, index, p.ocube_center[s], p.ocube_half[s], p.ocube_axis.sub(3 * int64_t(s), 3).data());
    else if (p.kind[i] == kPrimTet)
      add_tet(vertex, index, p.tet_vertex.sub(4 * int64_t(s), 4).data());
    else
      throw std::invalid_argument("Embree scene: trimtopes and mesh triangles are not triangulated");
  }
  triangles_ = index.size() / 3;

  // One triangle geometry; Embree's buffers pad for its 16-byte vertex loads.
  const auto t0 = std::chrono::steady_clock::now();
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error("Embree: rtcNewDevice failed");
  device_ = device;
  RTCScene scene = rtcNewScene(device);
  scene_ = scene;
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), vertex.size()));
  auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(uint32_t), triangles_));
  check(device, "allocating buffers");
  for (size_t k = 0; k < vertex.size(); ++k) {
    vb[3 * k] = float(vertex[k].x);
    vb[3 * k + 1] = float(vertex[k].y);
    vb[3 * k + 2] = float(vertex[k].z);
  }
  std::copy(index.begin(), index.end(), ib);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  check(device, "building the scene");
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string EmbreeScene::version() {
  return RTC_VERSION_STRING;
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

float EmbreeScene::nearest(Vec3 o, Vec3 d, float tnear, float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = float(o.x);
  rh.ray.org_y = float(o.y);
  rh.ray.org_z = float(o.z);
  rh.ray.dir_x = float(d.x);
  rh.ray.dir_y = float(d.y);
  rh.ray.dir_z = float(d.z);
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(static_cast<RTCScene>(scene_), &context, &rh);
  return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
}

EmbreeScene::PrimaryTrace EmbreeScene::trace_primary(const CameraFrame& camera, int spp) const {
  PrimaryTrace out;
  out.depth.assign(size_t(camera.width) * size_t(camera.height), INFINITY);
  const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 4)
  for (int32_t y = 0; y < camera.height; ++y)
    for (int32_t x = 0; x < camera.width; ++x)
      for (int k = 0; k < spp; ++k) {
        real u, v;
        pixel_sample(k, spp, &u, &v);
        const Ray r = camera_ray(camera, real(x) + u, real(y) + v);
        const float t = nearest(r.o, r.d);
        if (k == 0) out.depth[size_t(y) * size_t(camera.width) + size_t(x)] = t;
      }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace pd
