// stb_image's PNG reader for the tests that read images back, compiled into each test file that
// includes it (internal linkage), and read_png: a PNG file as 8-bit RGB.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace pd::testing_png {

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // 3 bytes per pixel, rows top to bottom; empty when unreadable
  const unsigned char* at(int x, int y) const { return &rgb[3 * (size_t(y) * size_t(width) + size_t(x))]; }
};

// The PNG at `path` as RGB (an empty image when it cannot be read).
static inline Png read_png(const std::string& path) {
  Png p;
  int comp = 0;
  unsigned char* data = stbi_load(path.c_str(), &p.width, &p.height, &comp, 3);
  if (data) p.rgb.assign(data, data + 3 * size_t(p.width) * size_t(p.height));
  stbi_image_free(data);
  return p;
}

}  // namespace pd::testing_png
