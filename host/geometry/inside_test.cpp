#include "host/geometry/inside_test.h"

#include <algorithm>
#include <cmath>

namespace pd {

namespace {

// Side of the point (y, z) + (eps, eps^2) relative to the line u -> v in the (y, z) plane, for
// u < v by index: +1 left, -1 right; never 0 for distinct projected vertices.
int side(const Vec3d& u, const Vec3d& v, double y, double z) {
  const double e = (v[1] - u[1]) * (z - u[2]) - (v[2] - u[2]) * (y - u[1]);
  if (e != 0) return e > 0 ? 1 : -1;
  // e(p + (eps, eps^2)) = e(p) - eps (v_z - u_z) + eps^2 (v_y - u_y)
  if (v[2] != u[2]) return u[2] > v[2] ? 1 : -1;
  if (v[1] != u[1]) return v[1] > u[1] ? 1 : -1;
  return 0;
}

// Side test of the triangle edge a -> b (vertex ids), evaluated in canonical order.
int edge_side(const TriMesh& m, int32_t a, int32_t b, double y, double z) {
  return a < b ? side(m.vertices[a], m.vertices[b], y, z) : -side(m.vertices[b], m.vertices[a], y, z);
}

// floor(x) clamped to [0, n - 1] before it becomes an int (a flat or huge mesh's ratios reach
// 1e150; converting those is undefined).
int bin_of(double x, int n) {
  if (!(x >= 1)) return 0;
  return x >= double(n - 1) ? n - 1 : int(x);
}

}  // namespace

InsideTest::InsideTest(const TriMesh& mesh) : mesh_(&mesh), box_(bounds(mesh)) {
  // Bins over (y, z): about one triangle per bin on average.
  const double sy = std::max(box_.size()[1], 1e-300), sz = std::max(box_.size()[2], 1e-300);
  const double cell = std::sqrt(sy * sz / std::max<double>(1, double(mesh.triangles.size())));
  inv_cell_ = 1 / cell;
  ny_ = 1 + bin_of(std::ceil(sy / cell) - 1, 4096);  // 1 to 4096 bins a side
  nz_ = 1 + bin_of(std::ceil(sz / cell) - 1, 4096);
  inv_cell_ = std::min(double(ny_) / sy, double(nz_) / sz);
  y0_ = box_.lo[1];
  z0_ = box_.lo[2];
  auto bin_range = [&](const Triangle& t, int lo[2], int hi[2]) {
    for (int a = 0; a < 2; ++a) {
      const double origin = a == 0 ? y0_ : z0_;
      const int n = a == 0 ? ny_ : nz_;
      double mn = HUGE_VAL, mx = -HUGE_VAL;
      for (int32_t v : t) {
        mn = std::fmin(mn, mesh.vertices[v][1 + a]);
        mx = std::fmax(mx, mesh.vertices[v][1 + a]);
      }
      lo[a] = bin_of((mn - origin) * inv_cell_, n);
      hi[a] = bin_of((mx - origin) * inv_cell_, n);
    }
  };
  // Counting pass, then fill.
  bin_start_.assign(size_t(ny_) * nz_ + 1, 0);
  int lo[2], hi[2];
  for (const Triangle& t : mesh.triangles) {
    bin_range(t, lo, hi);
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) ++bin_start_[size_t(j) * ny_ + i + 1];
  }
  for (size_t b = 1; b < bin_start_.size(); ++b) bin_start_[b] += bin_start_[b - 1];
  bin_triangles_.resize(size_t(bin_start_.back()));
  std::vector<int64_t> fill(bin_start_.begin(), bin_start_.end() - 1);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    bin_range(mesh.triangles[t], lo, hi);
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) bin_triangles_[size_t(fill[size_t(j) * ny_ + i]++)] = int32_t(t);
  }
}

void InsideTest::crossings(double y, double z, std::vector<Crossing>& xs) const {
  xs.clear();
  if (!(y >= box_.lo[1] && y <= box_.hi[1] && z >= box_.lo[2] && z <= box_.hi[2])) return;
  const int i = bin_of((y - y0_) * inv_cell_, ny_), j = bin_of((z - z0_) * inv_cell_, nz_);
  const size_t bin = size_t(j) * ny_ + i;
  for (int64_t k = bin_start_[bin]; k < bin_start_[bin + 1]; ++k) {
    const Triangle& t = mesh_->triangles[size_t(bin_triangles_[size_t(k)])];
    const int s0 = edge_side(*mesh_, t[0], t[1], y, z);
    if (s0 == 0 || edge_side(*mesh_, t[1], t[2], y, z) != s0 || edge_side(*mesh_, t[2], t[0], y, z) != s0)
      continue;
    // The ray passes through this triangle: x of its plane at (y, z).
    const Vec3d& a = mesh_->vertices[t[0]];
    const Vec3d n = cross(mesh_->vertices[t[1]] - a, mesh_->vertices[t[2]] - a);
    if (n[0] == 0) continue;
    // The crossing's sign is the triangle's projected orientation, which the exact side tests
    // give (n[0]'s sign, rounded, could disagree on a sliver).
    xs.push_back({a[0] - (n[1] * (y - a[1]) + n[2] * (z - a[2])) / n[0], s0});
  }
  std::sort(xs.begin(), xs.end(), [](const Crossing& a, const Crossing& b) { return a.x < b.x; });
}

bool InsideTest::inside(const Vec3d& p) const {
  thread_local std::vector<Crossing> xs;
  crossings(p[1], p[2], xs);
  return inside_of_row(xs, p[0]);
}

bool inside_of_row(const std::vector<InsideTest::Crossing>& xs, double x) {
  int winding = 0;
  for (auto c = std::upper_bound(xs.begin(), xs.end(), x,
                                 [](double v, const InsideTest::Crossing&k) { return v < k.x; });
       c != xs.end(); ++c)
    winding += c->sign;
  return winding != 0;
}

RowWalk::RowWalk(const std::vector<InsideTest::Crossing>& xs) : xs_(xs) {
  for (const InsideTest::Crossing& c : xs) winding_ += c.sign;
}

bool RowWalk::inside(double x) {
  while (next_ < xs_.size() && xs_[next_].x <= x) winding_ -= xs_[next_++].sign;
  return winding_ != 0;
}

}  // namespace pd
