#include "render/environment.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

// stb_image's Radiance .hdr reader only, with internal linkage.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_HDR
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace pd {

namespace {

[[noreturn]] void cannot_read(const std::string& path, const std::string& why) {
  throw EnvironmentError("cannot read environment '" + path + "': " + why +
                         " (allowed: a Radiance .hdr (RGBE) image in latitude-longitude layout, "
                         "twice as wide as high)");
}

// stb_image's reader through callbacks that note a read past the file's end: stb hands a
// decoder zeros there, so a truncated file would decode to black texels without an error.
struct CountingFile {
  std::FILE* file;
  bool read_past_end = false;

  static int read(void* user, char* data, int size) {
    auto* f = static_cast<CountingFile*>(user);
    const size_t n = std::fread(data, 1, size_t(size), f->file);
    if (n == 0) f->read_past_end = true;
    return int(n);
  }
  static void skip(void* user, int n) { std::fseek(static_cast<CountingFile*>(user)->file, n, SEEK_CUR); }
  static int eof(void* user) { return std::feof(static_cast<CountingFile*>(user)->file); }
};

}  // namespace

EnvironmentMap load_environment(const std::string& path) {
  // Open first, so that a missing or unreadable file gets the system's reason.
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) cannot_read(path, std::strerror(errno));
  if (!stbi_is_hdr_from_file(file.get())) cannot_read(path, "not a Radiance .hdr file");
  int w = 0, h = 0, channels = 0;
  CountingFile reader{file.get()};
  const stbi_io_callbacks callbacks{&CountingFile::read, &CountingFile::skip, &CountingFile::eof};
  const std::unique_ptr<float, void (*)(void*)> data(
      stbi_loadf_from_callbacks(&callbacks, &reader, &w, &h, &channels, 3), &stbi_image_free);
  if (reader.read_past_end)
    cannot_read(path, w > 0 && h > 0 ? "truncated: the file ends before its " + std::to_string(w) + " x " +
                                           std::to_string(h) + " texels do"
                                     : std::string("truncated"));
  if (!data) cannot_read(path, std::string("the decoder failed: ") + stbi_failure_reason());
  if (w != 2 * h) cannot_read(path, std::to_string(w) + " x " + std::to_string(h) + " texels");
  EnvironmentMap m;
  m.path = path;
  m.width = w;
  m.height = h;
  m.texel.resize(size_t(w) * size_t(h));
  const float* p = data.get();
  for (Vec3& t : m.texel) {
    t = {real(p[0]), real(p[1]), real(p[2])};
    p += 3;
  }
  m.sh = environment_sh9(m);
  return m;
}

Sh9 environment_sh9(const EnvironmentMap& map) {
  // Each texel covers mu = cos(theta) in [mu1, mu0] and phi in [phi0, phi1]; with
  // x = sqrt(1 - mu^2) cos(phi), y = mu, z = sqrt(1 - mu^2) sin(phi) and d omega = d mu d phi, every
  // Y_lm (a polynomial in x, y, z) integrates over the patch as a sum of products of a mu integral
  // (per row) and a phi integral (per column), in closed form.
  const double pi = 3.14159265358979323846;
  struct Row {
    double one, mu, root, mu_root, one_minus_mu2, mu2;  // integrals over [mu1, mu0]
  };
  std::vector<Row> rows(size_t(map.height));
  for (int32_t j = 0; j < map.height; ++j) {
    const double mu0 = std::cos(pi * j / map.height), mu1 = std::cos(pi * (j + 1) / map.height);
    auto root = [](double m) { return 0.5 * (m * std::sqrt(1 - m * m) + std::asin(m)); };
    auto mu_root = [](double m) { return -std::pow(1 - m * m, 1.5) / 3; };
    auto quad = [](double m) { return m - m * m * m / 3; };
    rows[size_t(j)] = {mu0 - mu1,
                       0.5 * (mu0 * mu0 - mu1 * mu1),
                       root(mu0) - root(mu1),
                       mu_root(mu0) - mu_root(mu1),
                       quad(mu0) - quad(mu1),
                       (mu0 * mu0 * mu0 - mu1 * mu1 * mu1) / 3};
  }
  struct Column {
    double one, cos, sin, sin2, cos2, sin_cos;  // integrals over [phi0, phi1]
  };
  std::vector<Column> columns(size_t(map.width));
  for (int32_t i = 0; i < map.width; ++i) {
    // u = 0.5 + phi / (2 pi) (environment.h).
    const double p0 = 2 * pi * (double(i) / map.width - 0.5), p1 = 2 * pi * (double(i + 1) / map.width - 0.5);
    const double d = p1 - p0, s2 = std::sin(2 * p1) - std::sin(2 * p0);
    columns[size_t(i)] = {d,
                          std::sin(p1) - std::sin(p0),
                          std::cos(p0) - std::cos(p1),
                          0.5 * d - 0.25 * s2,
                          0.5 * d + 0.25 * s2,
                          0.5 * (std::sin(p1) * std::sin(p1) - std::sin(p0) * std::sin(p0))};
  }
  // The normalisation constants of sh9_basis.
  const double k0 = 0.282094792, k1 = 0.488602512, k2 = 1.092548431, k6 = 0.315391565, k8 = 0.546274215;
  double sum[9][3] = {};
  for (int32_t j = 0; j < map.height; ++j) {
    const Row& r = rows[size_t(j)];
    for (int32_t i = 0; i < map.width; ++i) {
      const Column& c = columns[size_t(i)];
      const double y[9] = {k0 * r.one * c.one,
                           k1 * r.mu * c.one,
                           k1 * r.root * c.sin,
                           k1 * r.root * c.cos,
                           k2 * r.mu_root * c.cos,
                           k2 * r.mu_root * c.sin,
                           k6 * (3 * r.one_minus_mu2 * c.sin2 - r.one * c.one),
                           k2 * r.one_minus_mu2 * c.sin_cos,
                           k8 * (r.one_minus_mu2 * c.cos2 - r.mu2 * c.one)};
      const Vec3 L = map.texel[size_t(j) * size_t(map.width) + size_t(i)];
      for (int k = 0; k < 9; ++k) {
        sum[k][0] += y[k] * L.x;
        sum[k][1] += y[k] * L.y;
        sum[k][2] += y[k] * L.z;
      }
    }
  }
  Sh9 out;
  for (int k = 0; k < 9; ++k) out.c[k] = {real(sum[k][0]), real(sum[k][1]), real(sum[k][2])};
  return out;
}

}  // namespace pd
