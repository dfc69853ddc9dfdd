// sRGB encoding and PNG output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/io/png_file.h"

#include "tests/support/stb_png.h"

namespace pd {
namespace {

namespace fs = std::filesystem;

uint32_t big_endian32(const std::string& s, size_t at) {
  return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 |
         uint32_t(uint8_t(s[at + 2])) << 8 | uint32_t(uint8_t(s[at + 3]));
}

ImageRGB8 test_image(int w, int h) {
  ImageRGB8 im;
  im.width = w;
  im.height = h;
  for (int i = 0; i < 3 * w * h; ++i) im.rgb.push_back(uint8_t(i * 37 % 256));
  return im;
}

TEST(Srgb, EncodesKnownValues) {
  EXPECT_EQ(linear_to_srgb8(0), 0);
  EXPECT_EQ(linear_to_srgb8(1), 255);
  EXPECT_EQ(linear_to_srgb8(real(0.5)), 188);
  EXPECT_EQ(linear_to_srgb8(real(0.0015654)), 5);  // linear segment: 12.92 v 255 = 5.16
  EXPECT_EQ(linear_to_srgb8(-3), 0);
  EXPECT_EQ(linear_to_srgb8(7), 255);
}

TEST(Png, HasSignatureAndHeaderAndDecodesBack) {
  const ImageRGB8 im = test_image(5, 3);
  const std::string png = encode_png(im);
  ASSERT_GT(png.size(), 33u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(big_endian32(png, 8), 13u);  // IHDR length
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(big_endian32(png, 16), 5u);  // width
  EXPECT_EQ(big_endian32(png, 20), 3u);  // height
  EXPECT_EQ(uint8_t(png[24]), 8);        // bit depth
  EXPECT_EQ(uint8_t(png[25]), 2);        // colour type: RGB
  int w = 0, h = 0, comp = 0;
  uint8_t* pixels =
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(png.data()), int(png.size()), &w, &h, &comp, 3);
  ASSERT_NE(pixels, nullptr);
  EXPECT_EQ(w, 5);
  EXPECT_EQ(h, 3);
  EXPECT_EQ(std::vector<uint8_t>(pixels, pixels + 45), im.rgb);
  stbi_image_free(pixels);
}

TEST(Png, WritesTheFileAndRejectsMismatchedBuffers) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("perifrac_png_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "a.png").string();
  const ImageRGB8 im = test_image(4, 4);
  write_png(path, im);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  EXPECT_EQ(bytes.str(), encode_png(im));
  fs::remove_all(dir);

  ImageRGB8 bad = im;
  bad.rgb.pop_back();
  EXPECT_THROW(encode_png(bad), std::invalid_argument);
}

TEST(Psnr, KnownValues) {
  const ImageRGB8 a = test_image(8, 4);
  EXPECT_EQ(psnr(a, a), INFINITY);
  // Every channel off by 1: MSE 1, PSNR 20 log10(255) = 48.13 dB.
  ImageRGB8 b = a;
  for (uint8_t& v : b.rgb) v = v == 255 ? 254 : uint8_t(v + 1);
  EXPECT_NEAR(psnr(a, b), 20 * std::log10(255.0), 1e-9);
  // One channel of 96 off by 255: MSE 255^2 / 96, PSNR 10 log10(96) = 19.82 dB.
  ImageRGB8 c = a;
  ASSERT_EQ(c.rgb[0], 0);
  c.rgb[0] = 255;
  EXPECT_NEAR(psnr(a, c), 10 * std::log10(96.0), 1e-9);
  EXPECT_THROW(psnr(a, test_image(4, 8)), std::invalid_argument);
}

}  // namespace
}  // namespace pd
