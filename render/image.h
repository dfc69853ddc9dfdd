// 8-bit sRGB images: the linear-to-sRGB encoding the renderer kernel applies per pixel, and
// PNG encoding (host/io/png_file.h writes the file).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "render/geometry.h"

namespace pd {

// Interleaved RGB, rows from top to bottom.
struct ImageRGB8 {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;

  const uint8_t* pixel(int x, int y) const {
    return rgb.data() + 3 * (size_t(y) * size_t(width) + size_t(x));
  }
};

// Linear intensity (clamped to [0, 1]) to an 8-bit sRGB value, rounded to nearest.
PD_HD inline uint8_t linear_to_srgb8(real v) {
  v = clamp01(v);
  const real s =
      v <= real(0.0031308) ? real(12.92) * v : real(1.055) * std::pow(v, real(1 / 2.4)) - real(0.055);
  return uint8_t(s * 255 + real(0.5));
}

// Peak signal-to-noise ratio of b against a over all channels, 10 log10(255^2 / MSE) in dB;
// INFINITY for identical images. Throws std::invalid_argument when the sizes differ.
double psnr(const ImageRGB8& a, const ImageRGB8& b);

// The image as PNG file bytes (stb_image_write, 8-bit RGB). Throws std::runtime_error if the
// encoder fails and std::invalid_argument if the pixel buffer does not match the size.
std::string encode_png(const ImageRGB8& image);

}  // namespace pd
