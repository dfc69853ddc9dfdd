#include "host/app/bench_two_level.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "render/traverse.h"

namespace pd {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Vec3 apply(const Eigen::Matrix3d& r, const Eigen::Vector3d& t, Vec3 p) {
  const Eigen::Vector3d q = r * Eigen::Vector3d(p.x, p.y, p.z) + t;
  return {real(q.x()), real(q.y()), real(q.z())};
}

Vec3 turn(const Eigen::Matrix3d& r, Vec3 v) {
  const Eigen::Vector3d q = r * Eigen::Vector3d(v.x, v.y, v.z);
  return {real(q.x()), real(q.y()), real(q.z())};
}

// Appends primitive i of `from` (a tetrahedron, cube or oriented cube) moved by (r, t) to `to`:
// tetrahedra moved, cubes turned (a cube stays axis-aligned under the identity).
void add_moved(PrimitiveSet& to, const PrimitiveSet& from, int32_t i, const Eigen::Matrix3d& r,
               const Eigen::Vector3d& t) {
  const size_t s = size_t(from.slot[size_t(i)]);
  const uint8_t kind = from.kind[size_t(i)];
  if (kind == kPrimTet) {
    const Vec3* v = &from.tet_vertex[4 * s];
    to.add_tet(apply(r, t, v[0]), apply(r, t, v[1]), apply(r, t, v[2]), apply(r, t, v[3]));
  } else if (kind == kPrimCube && r == Eigen::Matrix3d::Identity()) {
    to.add_cube(apply(r, t, from.cube_center[s]), from.cube_half[s]);
  } else if (kind == kPrimCube) {
    const Vec3 axis[3] = {turn(r, {1, 0, 0}), turn(r, {0, 1, 0}), turn(r, {0, 0, 1})};
    to.add_oriented_cube(apply(r, t, from.cube_center[s]), from.cube_half[s], axis);
  } else {
    const Vec3* a = &from.ocube_axis[3 * s];
    const Vec3 axis[3] = {turn(r, a[0]), turn(r, a[1]), turn(r, a[2])};
    to.add_oriented_cube(apply(r, t, from.ocube_center[s]), from.ocube_half[s], axis);
  }
}

// One fragment: its primitives in rest space, their kd-tree, its transform and the global ids.
struct Instance {
  PrimitiveSet prims;
  std::vector<int32_t> global;
  KdTree tree;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  Vec3 rt[3];  // rows of the rotation's transpose: world -> rest directions
};

// The nearest hit through the top-level tree: the renderer's walk with a full stack (it never
// restarts), whose leaves hold fragments instead of primitives. At each leaf the ray is taken into
// each fragment's rest frame and traced through its tree.
Hit trace_two_level(const KdTree& top, const std::vector<Instance>& inst, const Ray& ray, int64_t* entered) {
  const auto enter_fragments = [&](KdNode leaf, Hit* best) {
    for (uint32_t k = 0; k < leaf.prim_count(); ++k) {
      const Instance& f = inst[top.prim_index[leaf.first_prim + k]];
      const Vec3 q = ray.o - Vec3{real(f.translation.x()), real(f.translation.y()), real(f.translation.z())};
      const Ray local = make_ray({dot(f.rt[0], q), dot(f.rt[1], q), dot(f.rt[2], q)},
                                 {dot(f.rt[0], ray.d), dot(f.rt[1], ray.d), dot(f.rt[2], ray.d)}, ray.tmin,
                                 best->prim >= 0 ? best->t : ray.tmax);
      ++*entered;
      const Hit h = traverse_short_stack<kRenderStackSize>(f.tree.view(), f.prims.view(), local);
      if (h.prim >= 0 && (best->prim < 0 || h.t < best->t))
        *best = {f.global[size_t(h.prim)], h.t, turn(f.rotation, h.normal)};
    }
  };
  return walk_short_stack<kKdMaxDepth>(top.view(), ray, enter_fragments);
}

// The rest scene cut into about `fragments` blocks of cells in x and z, each block a fragment with
// its primitives in rest space and a rigid motion about its rest centre: turned up to 0.2 rad, moved
// up to 2% of the slab's width, as pieces are a little after breaking. No trees yet.
std::vector<Instance> make_fragments(const PrimitiveSet& rest, int64_t cells_x, int64_t cells_y,
                                     int64_t cells_z, int per_cell, int fragments) {
  const int64_t fx = std::max<int64_t>(1, std::lround(std::sqrt(double(fragments))));
  const int64_t fz = std::max<int64_t>(1, (fragments + fx - 1) / fx);
  std::vector<Instance> inst(size_t(fx * fz));
  uint64_t state = 12345;
  auto uniform = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) * 0x1p-53 * 2 - 1;
  };
  for (Instance& f : inst) {
    const Eigen::Vector3d axis = Eigen::Vector3d(uniform(), uniform(), uniform()).normalized();
    f.rotation = Eigen::AngleAxisd(0.2 * uniform(), axis).toRotationMatrix();
    f.translation = 0.02 * Eigen::Vector3d(uniform(), uniform(), uniform());
  }
  for (int32_t i = 0; i < rest.size(); ++i) {
    const int64_t cell = i / per_cell, x = cell % cells_x, z = cell / (cells_x * cells_y);
    Instance& f = inst[size_t((z * fz / cells_z) * fx + x * fx / cells_x)];
    f.global.push_back(i);
    add_moved(f.prims, rest, i, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  }
  // Each fragment turns about its rest centre: x -> R (x - c) + c + t.
  for (Instance& f : inst) {
    Box b{{0, 0, 0}, {0, 0, 0}};
    const std::vector<Box> boxes = f.prims.bounds();
    if (!boxes.empty()) b = boxes[0];
    for (const Box& e : boxes) b = {vmin(b.lo, e.lo), vmax(b.hi, e.hi)};
    const Eigen::Vector3d c(0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y), 0.5 * (b.lo.z + b.hi.z));
    f.translation += c - f.rotation * c;
    const Eigen::Matrix3d rt = f.rotation.transpose();
    for (int k = 0; k < 3; ++k) f.rt[k] = {real(rt(k, 0)), real(rt(k, 1)), real(rt(k, 2))};
  }
  return inst;
}

// The boxes of the fragments' rest trees moved by their motions (each the bounds of the moved
// corners).
std::vector<Box> moved_bounds(const std::vector<Instance>& inst) {
  std::vector<Box> moved(inst.size());
  for (size_t k = 0; k < inst.size(); ++k) {
    const Box& b = inst[k].tree.bounds;
    moved[k] = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (int c = 0; c < 8; ++c) {
      const Vec3 p = apply(inst[k].rotation, inst[k].translation,
                           {(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z});
      moved[k] = {vmin(moved[k].lo, p), vmax(moved[k].hi, p)};
    }
  }
  return moved;
}

}  // namespace

double depth_agreement(const std::vector<float>& a, const std::vector<float>& b) {
  size_t same = 0;
  for (size_t i = 0; i < a.size(); ++i)
    same +=
        std::isinf(a[i]) ? std::isinf(b[i]) : std::fabs(double(a[i]) - double(b[i])) <= 1e-4 * double(a[i]);
  return a.empty() ? 1.0 : double(same) / double(a.size());
}

TwoLevelReport measure_two_level(const PrimitiveSet& rest, int64_t cells_x, int64_t cells_y, int64_t cells_z,
                                 int per_cell, int fragments, const CameraFrame& camera,
                                 const KdBuildOptions& options) {
  std::vector<Instance> inst = make_fragments(rest, cells_x, cells_y, cells_z, per_cell, fragments);
  TwoLevelReport r;
  r.fragments = int32_t(inst.size());

  // Rest-space trees, once per fragment (in parallel over fragments).
  auto t0 = std::chrono::steady_clock::now();
  KdBuildOptions one = options;
  one.threads = 1;
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t k = 0; k < inst.size(); ++k) inst[k].tree = build_kdtree(inst[k].prims.bounds(), one);
  r.rest_build_seconds = seconds_since(t0);

  // Per frame, two levels: the top-level tree over the moved fragment bounds.
  t0 = std::chrono::steady_clock::now();
  const KdTree top = build_kdtree(moved_bounds(inst), options);
  r.top_build_seconds = seconds_since(t0);

  // Per frame, one level: the moved primitives and their tree.
  PrimitiveSet world;
  for (const Instance& f : inst)
    for (int32_t i = 0; i < f.prims.size(); ++i) add_moved(world, f.prims, i, f.rotation, f.translation);
  t0 = std::chrono::steady_clock::now();
  const KdTree tree = build_kdtree(world.bounds(), options);
  r.world_build_seconds = seconds_since(t0);

  // Primary rays both ways.
  const int64_t pixels = int64_t(camera.width) * camera.height;
  std::vector<float> one_depth(size_t(pixels), INFINITY), two_depth(size_t(pixels), INFINITY);
  t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 4)
  for (int32_t y = 0; y < camera.height; ++y)
    for (int32_t x = 0; x < camera.width; ++x) {
      const Hit h = traverse_short_stack<kRenderStackSize>(
          tree.view(), world.view(), camera_ray(camera, real(x) + real(0.5), real(y) + real(0.5)));
      if (h.prim >= 0) one_depth[size_t(y) * size_t(camera.width) + size_t(x)] = float(h.t);
    }
  r.world_trace_seconds = seconds_since(t0);
  int64_t entered = 0;
  t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : entered)
  for (int32_t y = 0; y < camera.height; ++y)
    for (int32_t x = 0; x < camera.width; ++x) {
      const Hit h =
          trace_two_level(top, inst, camera_ray(camera, real(x) + real(0.5), real(y) + real(0.5)), &entered);
      if (h.prim >= 0) two_depth[size_t(y) * size_t(camera.width) + size_t(x)] = float(h.t);
    }
  r.two_level_trace_seconds = seconds_since(t0);
  r.instances_per_ray = double(entered) / double(pixels);
  r.agreement = depth_agreement(one_depth, two_depth);
  return r;
}

}  // namespace pd
