#include "render/image.h"

#include <cmath>
#include <stdexcept>

// The one stb_image_write implementation of the project, with internal linkage.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace pd {

std::string encode_png(const ImageRGB8& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != 3 * size_t(image.width) * size_t(image.height))
    throw std::invalid_argument("encode_png: the pixel buffer does not match the image size");
  std::string bytes;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                              3 * image.width))
    throw std::runtime_error("encode_png: the PNG encoder failed");
  return bytes;
}

double psnr(const ImageRGB8& a, const ImageRGB8& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw std::invalid_argument("psnr: the images differ in size");
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(b.rgb[i]);
    sum += d * d;
  }
  if (sum == 0) return INFINITY;
  return 10 * std::log10(255.0 * 255.0 * double(a.rgb.size()) / sum);
}

}  // namespace pd
