// The renderer for one backend: uploads a scene, runs the per-pixel kernel through the
// backend's parallel_for and downloads the image. Included by render/renderer_cpu.cpp
// (CpuExec) and render/renderer_cuda.cu (CudaExec); the kernel body is one PD_HD source.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "cuda/device_array.h"
#include "cuda/kernel_stats.h"
#include "render/collider_hit.h"
#include "render/glass.h"
#include "render/renderer.h"
#include "render/traverse.h"

namespace pd {

constexpr int kMaxGlassPieces = 6;  // separate glass collections one primary ray passes through
// Pixels are handed out in tiles of one warp (8 x 4), so neighbouring threads trace
// neighbouring rays. Tile order is a fixed permutation of the image, so that the equal
// contiguous thread ranges of a static CPU schedule each get a spread of easy and hard tiles.
constexpr int kTileWidth = 8, kTileHeight = 4, kTilePixels = kTileWidth * kTileHeight;

struct PixelKernelParams {
  KdTreeView tree;
  PrimitivesView prims;
  ArrayView<const Vec3> albedo;
  ArrayView<const uint8_t> material;  // SurfaceMaterial per primitive; empty: all opaque
  real ior = real(1.5);               // index of refraction of glass
  real join_gap = 0;                  // union tolerance of touching elements (union_walk.h)
  CameraFrame camera;
  int32_t spp = 1;
  real exposure = 1;
  ShadingParams shading;
  int32_t tiles_x = 0;
  int64_t tiles = 0;
  int64_t tile_step = 1;          // coprime with `tiles`: thread tile k draws image tile k * step mod tiles
  ArrayView<uint32_t> ray_count;  // per pixel: the rays it traced (nearest-hit queries); empty: not kept
  ArrayView<const Collider> colliders;    // drawn as solids of `collider_albedo` (collider_hit.h)
  ArrayView<const float> collider_grids;  // the mesh colliders' distance grids
  Vec3 collider_albedo{0, 0, 0};
};

// Hit::prim of collider k: kColliderPrim - k (below -1, which is no hit).
constexpr int32_t kColliderPrim = -2;

// The nearest primitive, collider or floor crossing of `ray`: hit.prim >= 0 for a primitive,
// <= kColliderPrim for a collider; else *floor_t > 0 when the ray reaches the floor.
PD_HD inline Hit nearest(const PixelKernelParams& p, const Ray& ray, real* floor_t) {
  Hit hit = traverse_short_stack<kRenderStackSize>(p.tree, p.prims, ray);
  *floor_t = 0;
  const ShadingParams& s = p.shading;
  if (s.floor && ray.d.y != 0) {
    const real t = (s.floor_y - ray.o.y) / ray.d.y;
    if (t > ray.tmin && (hit.prim < 0 || t < hit.t)) {
      hit.prim = -1;
      *floor_t = t;
    }
  }
  if (p.colliders.size > 0) {
    real t = hit.prim >= 0 ? hit.t : (*floor_t > 0 ? *floor_t : ray.tmax);
    Vec3 normal;
    const int32_t k = nearest_collider(p.colliders, ray, &t, &normal, p.collider_grids.data());
    if (k >= 0) {
      hit.prim = kColliderPrim - k;
      hit.t = t;
      hit.normal = normal;
      *floor_t = 0;
    }
  }
  return hit;
}

// Radiance of a surface seen along `ray` that is not glass: the floor, an opaque primitive or
// the sky.
PD_HD inline Vec3 shade_surface(const PixelKernelParams& p, const Ray& ray, const Hit& hit, real floor_t) {
  const ShadingParams& s = p.shading;
  if (floor_t > 0) return shade_floor(s, ray.o + floor_t * ray.d, ray.d, floor_t);
  if (hit.prim == -1) return background_radiance(s, ray.d);
  // Shade the side facing the eye (an eye inside a primitive sees the exit face).
  const Vec3 n = dot(hit.normal, ray.d) > 0 ? -hit.normal : hit.normal;
  return shade_opaque(s, n, -ray.d, hit.prim >= 0 ? p.albedo[hit.prim] : p.collider_albedo);
}

PD_HD inline bool is_glass(const PixelKernelParams& p, int32_t prim) {
  return p.material && prim >= 0 && p.material[prim] == kMaterialGlass;
}

// Radiance arriving along a primary ray. Glass: the Fresnel-reflected part is looked up with one
// more ray (glass seen in a reflection shows the sky behind it), the refracted part crosses the
// collection (glass.h) and goes on to whatever lies behind, up to kMaxGlassPieces collections.
// `rays` counts the nearest-hit queries: the primary ray, reflection rays and the rays leaving
// glass collections.
PD_HD inline Vec3 trace_primary(const PixelKernelParams& p, Ray ray, uint32_t* rays) {
  Vec3 radiance{0, 0, 0};
  real weight = 1;
  for (int piece = 0;; ++piece) {
    real floor_t;
    ++*rays;
    const Hit hit = nearest(p, ray, &floor_t);
    if (!is_glass(p, hit.prim) || floor_t > 0) return radiance + weight * shade_surface(p, ray, hit, floor_t);
    if (piece == kMaxGlassPieces) return radiance + weight * background_radiance(p.shading, ray.d);
    // Entry into the collection: the face turned towards the ray.
    const Vec3 n = dot(hit.normal, ray.d) > 0 ? -hit.normal : hit.normal;
    const Vec3 x = ray.o + hit.t * ray.d;
    const Fresnel f = fresnel_dielectric(-dot(ray.d, n), real(1), p.ior);
    const Ray mirror = make_ray(x, reflect(ray.d, n), real(0.01) * p.join_gap, INFINITY);
    real mirror_floor;
    ++*rays;
    const Hit seen = nearest(p, mirror, &mirror_floor);
    radiance += (weight * f.reflect) * (is_glass(p, seen.prim) && !(mirror_floor > 0)
                                            ? background_radiance(p.shading, mirror.d)
                                            : shade_surface(p, mirror, seen, mirror_floor));
    if (!(f.transmit > 0)) return radiance;
    const GlassTransit g = glass_transit(p.tree, p.prims, x, refract(ray.d, n, real(1), p.ior, f.cos_t),
                                         hit.prim, p.ior, p.join_gap);
    weight *= f.transmit * g.weight;
    if (g.last < 0) return radiance + weight * background_radiance(p.shading, g.dir);
    ray = make_ray(g.point, g.dir, real(0.01) * p.join_gap, INFINITY);
  }
}

// Thread i: averages the pixel's samples and stores it as sRGB.
PD_HD inline void render_pixel(const PixelKernelParams& p, int64_t i, uint8_t* rgb) {
  const int64_t tile = (i / kTilePixels) * p.tile_step % p.tiles;
  const int32_t lane = int32_t(i % kTilePixels);
  const int32_t x = int32_t(tile % p.tiles_x) * kTileWidth + lane % kTileWidth;
  const int32_t y = int32_t(tile / p.tiles_x) * kTileHeight + lane / kTileWidth;
  if (x >= p.camera.width || y >= p.camera.height) return;
  Vec3 sum{0, 0, 0};
  uint32_t rays = 0;
  for (int k = 0; k < p.spp; ++k) {
    real u, v;
    pixel_sample(k, p.spp, &u, &v);
    sum += trace_primary(p, camera_ray(p.camera, real(x) + u, real(y) + v), &rays);
  }
  if (p.ray_count) p.ray_count[int64_t(y) * p.camera.width + x] = rays;
  const real scale = p.exposure / real(p.spp);
  uint8_t* out = rgb + 3 * (int64_t(y) * p.camera.width + x);
  out[0] = linear_to_srgb8(scale * sum.x);
  out[1] = linear_to_srgb8(scale * sum.y);
  out[2] = linear_to_srgb8(scale * sum.z);
}

template <class Exec>
void launch_render_pixels(Exec& ex, const PixelKernelParams& p, uint8_t* rgb, int64_t first, int64_t count) {
  ex.parallel_for_from("render/pixels", first, count, [=] PD_HD(int64_t i) { render_pixel(p, i, rgb); });
}

// A scene's primitive arrays copied to the backend, under PrimitiveSet's member names.
template <class Exec>
struct DevicePrimitives {
  DeviceArray<uint8_t, Exec> kind;
  DeviceArray<int32_t, Exec> slot;
  DeviceArray<Vec3, Exec> cube_center;
  DeviceArray<real, Exec> cube_half;
  DeviceArray<Vec3, Exec> tet_vertex;
  DeviceArray<TetPlane, Exec> tet_plane;
  DeviceArray<Vec3, Exec> trim_site;
  DeviceArray<int32_t, Exec> trim_plane_start;
  DeviceArray<Vec3, Exec> trim_plane_normal;
  DeviceArray<real, Exec> trim_plane_offset;
  DeviceArray<int32_t, Exec> trim_tri_start;
  DeviceArray<Vec3, Exec> trim_tri_vertex;
  DeviceArray<Box, Exec> trim_box;
  DeviceArray<Vec3, Exec> ocube_center;
  DeviceArray<real, Exec> ocube_half;
  DeviceArray<Vec3, Exec> ocube_axis;
  DeviceArray<Vec3, Exec> tri_vertex;
  DeviceArray<Vec3, Exec> tri_normal;
};

// The parts a frame is rendered in where RenderSettings::stop is set: up to 64, each of at least
// 2^18 pixels (an H200's resident threads) and 2^22 samples (a second or so on a CPU core).
inline constexpr int64_t kStopParts = 64, kStopPartPixels = int64_t(1) << 18,
                         kStopPartSamples = int64_t(1) << 22;

template <class Exec>
class RendererImpl final : public Renderer {
 public:
  explicit RendererImpl(std::string device) : exec_(&stats_), device_(std::move(device)) {}

  std::string device_name() const override { return device_; }

  RenderResult render_frame(const RenderScene& scene, const Camera& camera,
                            const RenderSettings& s) override {
    if (s.spp < 1) throw std::invalid_argument("render: samples per pixel must be at least 1");
    const PrimitiveSet& ps = scene.prims;
    if (scene.albedo.size() != ps.kind.size())
      throw std::invalid_argument("render: the scene needs one albedo per primitive");
    if (!scene.material.empty() && scene.material.size() != ps.kind.size())
      throw std::invalid_argument("render: the scene needs no material or one per primitive");

    // Upload the scene.
    const DevicePrimitives<Exec> prims = upload_primitives(ps);
    auto albedo = upload(scene.albedo);
    auto material = upload(scene.material);
    auto env = upload(s.environment ? s.environment->texel : std::vector<Vec3>());
    auto nodes = upload(scene.tree.nodes);
    auto prim_index = upload(scene.tree.prim_index);
    auto colliders = upload(scene.colliders);
    auto collider_grids = upload(scene.collider_grids);

    // Kernel parameters.
    PixelKernelParams p;
    p.camera = camera_frame(camera, s.width, s.height);
    p.prims = primitives_view(ps.size(), prims);
    p.tree = {view_of(nodes), view_of(prim_index), scene.tree.bounds};
    p.albedo = view_of(albedo);
    if (!scene.material.empty()) p.material = view_of(material);
    p.colliders = view_of(colliders);
    p.collider_grids = view_of(collider_grids);
    p.collider_albedo = scene.collider_albedo;
    p.ior = s.ior;
    p.join_gap = scene.join_gap;
    p.spp = s.spp;
    p.exposure = s.exposure;
    p.shading = make_shading_params(s);
    if (s.environment) p.shading.env = {view_of(env), s.environment->width, s.environment->height};
    p.tiles_x = (s.width + kTileWidth - 1) / kTileWidth;
    p.tiles = int64_t(p.tiles_x) * ((s.height + kTileHeight - 1) / kTileHeight);
    p.tile_step = std::max<int64_t>(1, std::llround(0.618 * double(p.tiles)));
    while (std::gcd(p.tile_step, p.tiles) != 1) ++p.tile_step;

    // Render and read back.
    DeviceArray<uint8_t, Exec> image(&exec_, 3 * size_t(s.width) * size_t(s.height));
    DeviceArray<uint32_t, Exec> ray_count(&exec_, s.count_rays ? size_t(s.width) * size_t(s.height) : 0);
    if (s.count_rays) p.ray_count = view_of(ray_count);
    const auto t0 = std::chrono::steady_clock::now();
    // In parts where a stop question is set and the frame is big, asked between them (the pixels
    // do not depend on it): each part keeps a GPU full and takes a while on a CPU.
    RenderResult r;
    const int64_t pixels = p.tiles * kTilePixels, samples = pixels * s.spp;
    const int64_t parts =
        s.stop ? std::clamp<int64_t>(std::min(pixels / kStopPartPixels, samples / kStopPartSamples), 1,
                                     kStopParts)
               : 1;
    for (int64_t k = 0; k < parts && !r.stopped; ++k) {
      const int64_t first = p.tiles * k / parts * kTilePixels, end = p.tiles * (k + 1) / parts * kTilePixels;
      launch_render_pixels(exec_, p, image.data(), first, end - first);
      exec_.flush_stats();  // waits for the device and reports kernel errors
      r.stopped = k + 1 < parts && s.stop();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.rays = int64_t(s.width) * s.height * s.spp;
    r.image.width = s.width;
    r.image.height = s.height;
    image.download(r.image.rgb);
    if (s.count_rays) {
      std::vector<uint32_t> counts;
      ray_count.download(counts);
      for (uint32_t c : counts) r.traced_rays += c;
    }
    return r;
  }

 private:
  template <class T>
  DeviceArray<T, Exec> upload(const std::vector<T>& host) {
    DeviceArray<T, Exec> a(&exec_, host.size());
    if (!host.empty()) a.upload(host);  // an empty vector may have no data pointer
    return a;
  }

  // The arrays of `ps` copied to the backend (uploaded in the order of DevicePrimitives' members).
  DevicePrimitives<Exec> upload_primitives(const PrimitiveSet& ps) {
    return {upload(ps.kind),
            upload(ps.slot),
            upload(ps.cube_center),
            upload(ps.cube_half),
            upload(ps.tet_vertex),
            upload(ps.tet_plane),
            upload(ps.trim_site),
            upload(ps.trim_plane_start),
            upload(ps.trim_plane_normal),
            upload(ps.trim_plane_offset),
            upload(ps.trim_tri_start),
            upload(ps.trim_tri_vertex),
            upload(ps.trim_box),
            upload(ps.ocube_center),
            upload(ps.ocube_half),
            upload(ps.ocube_axis),
            upload(ps.tri_vertex),
            upload(ps.tri_normal)};
  }

  KernelStats stats_;
  Exec exec_;
  std::string device_;
};

}  // namespace pd
